// Export benchmark (not a test): n gable houses (default 1000), one per parcel,
// written in every format; prints seconds per format. Target: < 5 s per format.
// Usage: c3d_export_bench [n] [out_dir]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "ifc_citygml/export.h"
#include "ifc_citygml/validate.h"
#include "tests/export_fixtures.h"

int main(int argc, char** argv) {
  int n = argc > 1 ? std::atoi(argv[1]) : 1000;
  std::string dir = argc > 2 ? argv[2] : (std::filesystem::temp_directory_path() / "c3d_export_bench").string();
  std::filesystem::remove_all(dir);
  c3d::BatchModel m = c3d::fixture::grid_batch(n);
  auto timed = [](const char* what, auto&& fn) {
    auto t0 = std::chrono::steady_clock::now();
    fn();
    double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("%-10s %7.3f s\n", what, s);
  };
  std::printf("%d buildings -> %s\n", n, dir.c_str());
  for (const char* f : {"gml", "gml3", "cityjson", "ifc", "obj", "step"})
    timed(f, [&] { c3d::export_formats(m, dir, {f}); });
  timed("validate", [&] { c3d::validate_model(m); });
  return 0;
}
