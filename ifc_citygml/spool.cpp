#include "ifc_citygml/spool.h"

#include <algorithm>
#include <filesystem>
#include <stdexcept>
#include <vector>

namespace c3d::exp {

// Bytes copied per read: large enough that copying costs what the disk does.
constexpr std::size_t kCopyBlock = 1 << 20;

Spool::Spool(const std::string& beside, const std::string& suffix) : path_(beside + suffix) {
  out_.open(path_, std::ios::binary | std::ios::in | std::ios::out | std::ios::trunc);
  if (!out_) throw std::runtime_error(path_ + ": cannot open for writing");
}

Spool::~Spool() {
  out_.close();
  std::error_code ec;
  std::filesystem::remove(path_, ec);
}

std::uint64_t Spool::size() {
  out_.flush();
  return std::uint64_t(out_.tellp());
}

void Spool::copy_to(std::ostream& to, std::uint64_t from, std::uint64_t count) {
  const std::uint64_t end = std::min(size(), count == UINT64_MAX ? UINT64_MAX : from + count);
  if (!out_) throw std::runtime_error(path_ + ": write failed");
  out_.seekg(std::streamoff(from));
  std::vector<char> buf(kCopyBlock);
  for (std::uint64_t at = from; at < end;) {
    const std::size_t n = std::size_t(std::min<std::uint64_t>(buf.size(), end - at));
    if (!out_.read(buf.data(), std::streamsize(n))) throw std::runtime_error(path_ + ": read failed");
    to.write(buf.data(), std::streamsize(n));
    at += n;
  }
  out_.seekp(0, std::ios::end);
}

void append_record(const std::string& path, const std::vector<std::uint8_t>& bytes) {
  const std::uint64_t n = bytes.size();
  std::ofstream out(path, std::ios::binary | std::ios::app);
  out.write(reinterpret_cast<const char*>(&n), sizeof n);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(n));
  if (!out) throw std::runtime_error(path + ": cannot be written");
}

}  // namespace c3d::exp
