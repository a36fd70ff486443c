#include "cadastre/batch/box_grid.h"

#include <algorithm>
#include <cmath>

namespace c3d {
namespace {

struct CellSpan {
  long x0, y0, x1, y1;
  long cells() const { return (x1 - x0 + 1) * (y1 - y0 + 1); }
};

CellSpan span_of(const Box& b, double side) {
  return {long(std::floor(b.min_x / side)), long(std::floor(b.min_y / side)), long(std::floor(b.max_x / side)),
          long(std::floor(b.max_y / side))};
}

std::uint64_t key(long x, long y) { return std::uint64_t(std::uint32_t(x)) << 32 | std::uint32_t(y); }

// Cells spanned, without overflow on an absurd box: capped past `cap` (and
// a box with a NaN spans more than any cap).
long cells_capped(const Box& b, double side, long cap) {
  const double w = std::floor(b.max_x / side) - std::floor(b.min_x / side) + 1;
  const double h = std::floor(b.max_y / side) - std::floor(b.min_y / side) + 1;
  return w * h <= double(cap) ? long(w * h) : cap + 1;
}

}  // namespace

BoxGrid::BoxGrid(std::vector<Box> boxes, double cell_m) : boxes_(std::move(boxes)), cell_m_(cell_m) {
  for (size_t i = 0; i < boxes_.size(); ++i) {
    const Box& b = boxes_[i];
    if (b.empty()) continue;
    if (cells_capped(b, cell_m_, kWideCells) > kWideCells) {
      wide_.push_back(std::uint32_t(i));
      continue;
    }
    const CellSpan s = span_of(b, cell_m_);
    for (long x = s.x0; x <= s.x1; ++x)
      for (long y = s.y0; y <= s.y1; ++y) grid_[key(x, y)].push_back(std::uint32_t(i));
  }
}

std::vector<size_t> BoxGrid::touching(const Box& box, double reach) const {
  std::vector<size_t> out;
  if (box.empty()) return out;
  const auto reaches = [&](size_t i) { return !boxes_[i].empty() && boxes_[i].grown(reach).touches(box); };
  const Box query = box.grown(reach);
  if (cells_capped(query, cell_m_, long(grid_.size())) > long(grid_.size())) {
    for (size_t i = 0; i < boxes_.size(); ++i)  // a query wider than the grid: every box once
      if (reaches(i)) out.push_back(i);
    return out;
  }
  for (std::uint32_t i : wide_)
    if (reaches(i)) out.push_back(i);
  const CellSpan s = span_of(query, cell_m_);
  for (long x = s.x0; x <= s.x1; ++x)
    for (long y = s.y0; y <= s.y1; ++y) {
      const auto it = grid_.find(key(x, y));
      if (it == grid_.end()) continue;
      for (std::uint32_t i : it->second)
        if (reaches(i)) out.push_back(i);
    }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace c3d
