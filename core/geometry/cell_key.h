#pragma once
// The cells of a uniform grid as hash-map keys: points near one another are
// found by looking in the cells round theirs rather than comparing each with
// all (welding.h, segment/clusters.cpp).
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace c3d {

template <int D>
using CellKey = std::array<int64_t, D>;

template <int D>
struct CellKeyHash {
  size_t operator()(const CellKey<D>& k) const {
    size_t h = 0;
    for (int64_t c : k) h = h * 1000003u ^ size_t(c);
    return h;
  }
};

// The cell, of side `cell`, holding the first D coordinates of v.
template <int D, class V>
CellKey<D> cell_key(const V& v, double cell) {
  CellKey<D> k;
  for (int d = 0; d < D; ++d) k[size_t(d)] = int64_t(std::floor(double(v[d]) / cell));
  return k;
}

// Calls f on the keys of the 3^D cells round k (k's own among them).
template <int D, class F>
void for_cells_round(const CellKey<D>& k, F&& f) {
  int count = 1;
  for (int d = 0; d < D; ++d) count *= 3;
  for (int i = 0; i < count; ++i) {
    CellKey<D> n = k;
    for (int d = 0, rest = i; d < D; ++d, rest /= 3) n[size_t(d)] += rest % 3 - 1;
    f(n);
  }
}

}  // namespace c3d
