#include "cadastre/batch/parcel_boxes.h"

#include <algorithm>
#include <cmath>

namespace c3d {
namespace {

// A few parcels across: a chunk's query visits few cells, a parcel lies in few.
constexpr double kCellM = 64;

std::uint64_t key(long x, long y) { return std::uint64_t(std::uint32_t(x)) << 32 | std::uint32_t(y); }

// Calls fn(key) for every grid cell the box meets.
template <class Fn>
void for_cells(const Box& b, Fn fn) {
  const long x0 = long(std::floor(b.min_x / kCellM)), x1 = long(std::floor(b.max_x / kCellM));
  const long y0 = long(std::floor(b.min_y / kCellM)), y1 = long(std::floor(b.max_y / kCellM));
  for (long x = x0; x <= x1; ++x)
    for (long y = y0; y <= y1; ++y) fn(key(x, y));
}

}  // namespace

ParcelBoxes::ParcelBoxes(const ParcelLayer& layer) {
  boxes_.reserve(layer.parcels.size());
  for (const Parcel& p : layer.parcels) boxes_.push_back(box_of(p.shape));
  for (size_t i = 0; i < boxes_.size(); ++i)
    if (!boxes_[i].empty()) for_cells(boxes_[i], [&](std::uint64_t k) { grid_[k].push_back(std::uint32_t(i)); });
}

std::vector<size_t> ParcelBoxes::touching(const Box& box, double reach) const {
  std::vector<size_t> out;
  if (box.empty()) return out;
  for_cells(box.grown(reach), [&](std::uint64_t k) {
    const auto it = grid_.find(k);
    if (it == grid_.end()) return;
    for (std::uint32_t i : it->second)
      if (boxes_[i].grown(reach).touches(box)) out.push_back(i);
  });
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace c3d
