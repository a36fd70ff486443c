#pragma once
// A temporary file beside an export that holds what must wait for later parts
// (a GML body before its envelope, CityJSON objects and vertices): streamed
// writers keep it on disk, not in memory. Removed when the Spool goes.
#include <cstdint>
#include <fstream>
#include <string>

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

}  // namespace c3d::exp
