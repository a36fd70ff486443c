#pragma once
// SHA-256 (FIPS 180-4) for input checksums, per-parcel input keys and the
// config fingerprint; small enough to keep here rather than pull a crypto
// library into the build.
#include <cstddef>
#include <cstdint>
#include <string>

namespace c3d {

class Sha256 {
 public:
  Sha256();
  void update(const void* data, std::size_t n);
  void update(const std::string& s) { update(s.data(), s.size()); }
  std::string hex();  // finishes the digest; call once

 private:
  void block(const std::uint8_t* p);
  std::uint32_t h_[8];
  std::uint8_t buf_[64];
  std::size_t fill_ = 0;
  std::uint64_t bytes_ = 0;
};

std::string sha256_hex(const std::string& data);
// Streams the file; throws InputError when it cannot be read.
std::string sha256_file(const std::string& path);

// An input file by its content, as a run records it.
struct InputFile {
  std::string path;
  std::string sha256;
  std::int64_t bytes = 0;  // -1 when the size cannot be read
  // What the file was to the run (cadastre/batch/batch.h, input_role); "" in
  // a record from before roles.
  std::string role;
};
// Reads the file once for its checksum; throws InputError when it cannot be read.
InputFile describe_input_file(const std::string& path);

}  // namespace c3d
