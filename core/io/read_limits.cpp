#include "core/io/read_limits.h"

#include <unistd.h>

#include <filesystem>
#include <sstream>

#include "core/error.h"

namespace c3d {

std::string coordinate_problem(double x, double y, double z, const std::string& where) {
  const double v[3] = {x, y, z};
  for (int k = 0; k < 3; ++k) {
    if (coordinate_ok(v[k])) continue;
    std::ostringstream s;
    s << (std::isfinite(v[k]) ? "coordinate beyond +-1e17" : "NaN/inf coordinate") << " at "
      << where << " (" << "xyz"[k] << " = " << v[k] << ")";
    return s.str();
  }
  return {};
}

void check_regular_file(const std::string& path) {
  std::error_code ec;  // the non-throwing calls: a 300-character name threw filesystem_error
  if (std::filesystem::is_regular_file(path, ec)) return;
  if (ec && ec != std::errc::no_such_file_or_directory)
    throw InputError(path, "cannot read (" + ec.message() + ")");
  throw InputError(path, std::filesystem::exists(path, ec) ? "not a regular file" : "file not found");
}

size_t physical_memory_bytes() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  return pages > 0 && page > 0 ? size_t(pages) * size_t(page) : 0;
}

}  // namespace c3d
