// Runs one-thread OpenMP regions inline. Debian's FLANN (inside PCL's kd-tree)
// opens `#pragma omp parallel num_threads(1)` around every single neighbour
// query; libgomp sets up and tears down a team for each, and on this
// project's machines that cost more than the queries themselves (Cimahi
// segmentation: 8.7 s of CPU with it, 2.7 s without; same results). A region
// of one thread is the body run once with orphaned work-sharing, which is what
// OpenMP specifies for it, so the body is called directly. Regions of more
// threads go to libgomp unchanged. The executable exports this definition, so
// the shared libraries' calls bind to it.
#include <dlfcn.h>

extern "C" void GOMP_parallel(void (*fn)(void*), void* data, unsigned num_threads, unsigned flags) {
  if (num_threads == 1) {
    fn(data);
    return;
  }
  using Real = void (*)(void (*)(void*), void*, unsigned, unsigned);
  static const Real real = reinterpret_cast<Real>(dlsym(RTLD_NEXT, "GOMP_parallel"));
  real(fn, data, num_threads, flags);
}
