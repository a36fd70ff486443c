#pragma once
// CPU time of the calling thread: a batch models (and meshes) parcels on
// several threads, and each stage's time is its own thread's.
#include <time.h>

namespace c3d {

inline double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

}  // namespace c3d
