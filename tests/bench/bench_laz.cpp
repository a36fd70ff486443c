// LAZ decoding speed (not a test): decodes a LAZ file's point records N times
// (read_las_records: file read + decode) and prints points per second of CPU
// time, i.e. per core (the decoder runs on one thread), and of wall time.
// Usage: c3d_bench_laz FILE.laz [repeats]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <exception>

#include "core/io/point_io.h"

namespace {

double cpu_seconds() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec + t.tv_nsec * 1e-9;
}

// The header's point record length (bytes 105-106).
double record_length(const char* path) {
  unsigned char h[107] = {};
  FILE* f = std::fopen(path, "rb");
  const size_t n = f ? std::fread(h, 1, sizeof h, f) : 0;
  if (f) std::fclose(f);
  return n == sizeof h ? h[105] | (h[106] << 8) : 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s FILE.laz [repeats]\n", argv[0]);
    return 2;
  }
  const int repeats = argc > 2 ? std::max(1, std::atoi(argv[2])) : 10;
  try {
    const size_t bytes = c3d::read_las_records(argv[1]).size();  // warm the page cache
    double best_cpu = 1e30, cpu_total = 0, wall_total = 0;
    for (int r = 0; r < repeats; ++r) {
      const double c0 = cpu_seconds();
      const auto t0 = std::chrono::steady_clock::now();
      c3d::read_las_records(argv[1]);
      const double cpu = cpu_seconds() - c0;
      wall_total += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      cpu_total += cpu;
      best_cpu = std::min(best_cpu, cpu);
    }
    const double points = double(bytes) / record_length(argv[1]);
    std::printf("%s: %.0f points, %d decodes: %.1f M points/s per core (CPU time; best %.1f), "
                "%.1f M points/s wall\n",
                argv[1], points, repeats, points * repeats / cpu_total / 1e6, points / best_cpu / 1e6,
                points * repeats / wall_total / 1e6);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
