#pragma once
// Boxes with a grid over them: which boxes a query box reaches, in time with
// the boxes near it rather than all of them (a million-parcel layer, a
// country's tiles). A box over more than kWideCells cells (a mistaken tile
// header, a region's whole extent) is kept aside and checked on every query,
// so that no box fills the grid.
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "cadastre/batch/tiles.h"

namespace c3d {

class BoxGrid {
 public:
  BoxGrid() = default;
  BoxGrid(std::vector<Box> boxes, double cell_m);
  size_t size() const { return boxes_.size(); }
  const Box& operator[](size_t i) const { return boxes_[i]; }
  // The boxes that, grown by `reach`, touch `box`; ascending.
  std::vector<size_t> touching(const Box& box, double reach) const;

 private:
  static constexpr long kWideCells = 4096;
  std::vector<Box> boxes_;
  double cell_m_ = 1;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grid_;  // cell -> boxes meeting it
  std::vector<std::uint32_t> wide_;
};

}  // namespace c3d
