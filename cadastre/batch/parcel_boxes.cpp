#include "cadastre/batch/parcel_boxes.h"

#include <algorithm>

namespace c3d {
namespace {

// A few parcels across: a chunk's query visits few cells, a parcel lies in few.
constexpr double kCellM = 64;

std::uint64_t key(const CellIndex& c) { return std::uint64_t(std::uint32_t(c.first)) << 32 | std::uint32_t(c.second); }

}  // namespace

ParcelBoxes::ParcelBoxes(const ParcelLayer& layer) {
  boxes_.reserve(layer.parcels.size());
  for (const Parcel& p : layer.parcels) boxes_.push_back(box_of(p.shape));
  for (size_t i = 0; i < boxes_.size(); ++i)
    for (const CellIndex& c : cells_touched({boxes_[i]}, kCellM)) grid_[key(c)].push_back(std::uint32_t(i));
}

std::vector<size_t> ParcelBoxes::touching(const Box& box, double reach) const {
  std::vector<size_t> out;
  if (box.empty()) return out;
  for (const CellIndex& c : cells_touched({box.grown(reach)}, kCellM)) {
    const auto it = grid_.find(key(c));
    if (it == grid_.end()) continue;
    for (std::uint32_t i : it->second)
      if (boxes_[i].grown(reach).touches(box)) out.push_back(i);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace c3d
