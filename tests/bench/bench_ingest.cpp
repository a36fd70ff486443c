// LAS ingest speed (not a test): reads a LAS file N times through
// read_point_cloud and prints points/s. Usage: c3d_bench_ingest FILE.las [repeats]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>

#include "core/io/point_io.h"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s FILE.las [repeats]\n", argv[0]);
    return 2;
  }
  const int repeats = argc > 2 ? std::max(1, std::atoi(argv[2])) : 20;
  try {
    c3d::read_point_cloud(argv[1]);  // warm the page cache: measure parsing, not the disk
    double best = 1e30, total = 0;
    size_t points = 0;
    for (int r = 0; r < repeats; ++r) {
      auto t0 = std::chrono::steady_clock::now();
      c3d::PointCloud c = c3d::read_point_cloud(argv[1]);
      double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      points = c.points.size();
      best = std::min(best, s);
      total += s;
    }
    double mean = total / repeats;
    std::printf("%s: %zu points, %d reads, mean %.2f ms (%.1f M points/s), best %.2f ms "
                "(%.1f M points/s)\n",
                argv[1], points, repeats, mean * 1e3, points / mean / 1e6, best * 1e3,
                points / best / 1e6);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
