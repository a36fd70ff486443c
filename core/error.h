#pragma once
// One exception type for bad input: the message always names the file (or the
// parcel) and the problem, so the CLI can print it as one clear line.
#include <stdexcept>
#include <string>

namespace c3d {

class InputError : public std::runtime_error {
 public:
  InputError(const std::string& where, const std::string& problem)
      : std::runtime_error(where + ": " + problem) {}
  // The same error with a detail appended, e.g. GDAL's own last word: "<what>; <detail>".
  InputError appended(const std::string& detail) const { return InputError(std::string(what()) + "; " + detail); }

 private:
  explicit InputError(const std::string& text) : std::runtime_error(text) {}
};

}  // namespace c3d
