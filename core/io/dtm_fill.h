#pragma once
// Filling a DTM's NoData cells (NaN in Dtm::z): GDALFillNodata's inverse
// distance, the nearest valid cell beyond its reach, and building-size holes
// with the terrain's trend. Used on a whole grid, or on one tile of a raster
// grown by a margin (DtmSource).
#include <cstdint>
#include <vector>

#include "core/types.h"

namespace c3d {

// A tile's part of the grid being filled: the cells kept [keep_x0, keep_x1) x
// [keep_y0, keep_y1), the inverse-distance search bounded by max_search, and
// which sides of the grid are cut out of a larger raster (a hole touching
// such a side is larger than the grid shows: it keeps the plain fill).
struct FillTile {
  int max_search = 0;
  int keep_x0 = 0, keep_y0 = 0, keep_x1 = 0, keep_y1 = 0;
  bool cut_left = false, cut_top = false, cut_right = false, cut_bottom = false;
};

// Fills the NaN cells of dtm.z and sets dtm.nodata_share. Without a tile the
// search reaches the whole grid; an all-NaN grid is an InputError.
void fill_holes(Dtm& dtm, const FillTile* tile = nullptr);

// The terrain far from any valid height, for a raster's cells beyond the
// fill's reach: blocks of kBlockCells x kBlockCells cells, each the mean of
// its valid heights, an empty block taking its nearest non-empty block's
// (one breadth-first search over the blocks), read between block centres
// bilinearly. Built from one pass over the raster: linear in its cells, and
// a cell's height depends on the raster alone.
class FarTerrain {
 public:
  static constexpr int kBlockCells = 16;
  FarTerrain() = default;
  FarTerrain(int nx, int ny);
  // Rows [y0, y0 + rows) of the raster, row-major, NaN for NoData.
  void add_rows(const std::vector<float>& z, int y0);
  // Every block given a height; false when the raster has no valid height.
  bool finish();
  float height(int x, int y) const;

 private:
  int nx_ = 0, ny_ = 0, bx_ = 0, by_ = 0;
  std::vector<double> sum_;
  std::vector<uint32_t> count_;
  std::vector<float> block_z_;
};

}  // namespace c3d
