#pragma once
// Filling a DTM's NoData cells (NaN in Dtm::z): GDALFillNodata's inverse
// distance, the nearest valid cell beyond its reach, and building-size holes
// with the terrain's trend. Used on a whole grid, or on one tile of a raster
// grown by a margin (DtmSource).
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

}  // namespace c3d
