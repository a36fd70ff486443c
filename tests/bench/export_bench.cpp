// Export benchmark (not a test): n gable houses (default 1000), one per parcel,
// written in every format; prints seconds per format. Target: < 5 s per format.
// Usage: c3d_export_bench [n] [out_dir]
//        c3d_export_bench n out_dir --streamed-3dtiles
// The second form feeds the 3D Tiles writer pages of 200 houses made one at a
// time, as a batch does, so the process's peak memory is the writer's own.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <cstring>
#include <sys/resource.h>

#include "ifc_citygml/export.h"
#include "ifc_citygml/validate.h"
#include "tests/export_fixtures.h"

// Houses [first, first + count) of grid_batch's grid, as one page with a CRS.
c3d::BatchModel grid_page(int first, int count) {
  c3d::BatchModel m = c3d::fixture::grid_houses(first, count);
  m.crs_wkt = "EPSG:32748";
  return m;
}

int streamed_tiles(int n, const std::string& dir) {
  const auto t0 = std::chrono::steady_clock::now();
  auto w = c3d::tileset_writer(grid_page(0, 0), dir);
  for (int first = 0; first < n; first += 200) w->add(grid_page(first, std::min(200, n - first)));
  w->finish();
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  std::printf("3dtiles streamed: %d buildings, %.3f s, peak memory %.1f MB\n", n,
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), u.ru_maxrss / 1024.0);
  return 0;
}

int main(int argc, char** argv) {
  int n = argc > 1 ? std::atoi(argv[1]) : 1000;
  std::string dir = argc > 2 ? argv[2] : (std::filesystem::temp_directory_path() / "c3d_export_bench").string();
  std::filesystem::remove_all(dir);
  if (argc > 3 && std::strcmp(argv[3], "--streamed-3dtiles") == 0) return streamed_tiles(n, dir);
  c3d::BatchModel m = c3d::fixture::grid_batch(n);
  m.crs_wkt = "EPSG:32748";
  auto timed = [](const char* what, auto&& fn) {
    auto t0 = std::chrono::steady_clock::now();
    fn();
    double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("%-10s %7.3f s\n", what, s);
  };
  std::printf("%d buildings -> %s\n", n, dir.c_str());
  for (const char* f : {"gml", "gml3", "cityjson", "ifc", "obj", "step", "3dtiles"})
    timed(f, [&] { c3d::export_formats(m, dir, {f}); });
  timed("validate", [&] { c3d::validate_model(m); });
  return 0;
}
