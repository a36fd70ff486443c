#pragma once
// A temporary file beside an export that holds what must wait for later parts
// (a GML body before its envelope, CityJSON objects and vertices): streamed
// writers keep it on disk, not in memory. Removed when the Spool goes.
#include <cstdint>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace c3d::exp {

class Spool {
 public:
  // The file is `beside` + suffix (so the same folder, and a name no output uses).
  Spool(const std::string& beside, const std::string& suffix);
  ~Spool();
  Spool(const Spool&) = delete;
  Spool& operator=(const Spool&) = delete;

  std::ostream& out() { return out_; }
  std::uint64_t size();  // bytes written so far
  // Appends the bytes [from, from + count) (default: all) to `to`.
  void copy_to(std::ostream& to, std::uint64_t from = 0, std::uint64_t count = UINT64_MAX);

 private:
  std::string path_;
  std::fstream out_;
};

// Records appended to a file, each after its length in bytes (a cell's
// buildings as the pages bring them), and read back in the order written.
void append_record(const std::string& path, const std::vector<std::uint8_t>& bytes);
template <typename F>
void read_records(const std::string& path, F&& each) {
  std::ifstream in(path, std::ios::binary);
  std::uint64_t n = 0;
  while (in.read(reinterpret_cast<char*>(&n), sizeof n)) {
    std::vector<std::uint8_t> bytes(n);
    if (!in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(n)))
      throw std::runtime_error(path + ": a record cut short");
    each(bytes);
  }
}

}  // namespace c3d::exp
