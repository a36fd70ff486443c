#include "core/io/file_names.h"

#include "core/io/sha256.h"

namespace c3d {
namespace {

constexpr size_t kMaxKeptLength = 80;    // well under any file system's 255-byte name limit
constexpr size_t kMaxPrefixLength = 60;  // the readable part of a changed name
constexpr size_t kHashDigits = 16;       // 64 bits: no accidental collision in any layer

bool safe_char(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '.' ||
         c == '_' || c == '-';
}

}  // namespace

std::string file_stem_for_id(const std::string& id) {
  bool keep = !id.empty() && id.size() <= kMaxKeptLength && id[0] != '.' && id[0] != '-';
  for (char c : id) keep = keep && safe_char(c);
  if (keep) return id;
  std::string prefix;
  for (char c : id.substr(0, kMaxPrefixLength)) prefix += safe_char(c) ? c : '_';
  if (!prefix.empty() && (prefix[0] == '.' || prefix[0] == '-')) prefix[0] = '_';  // no hidden file, no option
  return prefix + "~" + sha256_hex(id).substr(0, kHashDigits);
}

}  // namespace c3d
