#pragma once
// Digital terrain models: any GDAL raster, or a grid built from ground points.
// NoData holes (typically under buildings) are always filled, so that walls can
// be extruded down to the terrain everywhere.
#include <string>
#include <vector>

#include "core/types.h"

namespace c3d {

// The most cells a DTM may have on this machine: kMaxDtmCells, or fewer where
// half the physical memory holds fewer (core/io/read_limits.h).
size_t dtm_cell_budget();

// Band 1 of any raster GDAL opens; NoData filled by GDALFillNodata, then any
// remaining hole by its nearest valid cell. Throws InputError on unreadable,
// rotated or all-NoData rasters, and on a raster of more than max_cells cells
// (checked before anything is allocated).
Dtm read_dtm(const std::string& path, size_t max_cells = dtm_cell_budget());

enum class DtmCell { Min, Mean };

// Grid of the ground points' min (or mean) z with the given cell size; empty
// cells filled like read_dtm. source names the data for error messages; a grid
// over dtm_cell_budget() cells is an InputError.
Dtm dtm_from_points(const std::vector<Vec3>& ground, const std::string& crs_wkt,
                    double cell_m = 1.0, DtmCell stat = DtmCell::Min,
                    const std::string& source = "ground points");

// dtm_from_points (DtmCell::Min) for ground points streamed in parts: the grid
// from their extent (known first: a pass of its own), each part added, then the
// holes filled. The same points give the same grid, whatever the parts.
class GroundDtmBuilder {
 public:
  GroundDtmBuilder(double min_x, double min_y, double max_x, double max_y, const std::string& crs_wkt,
                   double cell_m, const std::string& source);
  void add(const std::vector<Vec3>& ground);  // each cell keeps its lowest point
  Dtm finish();                                // holes filled; the builder is spent

  size_t cells() const { return dtm_.z.size(); }
  size_t cell_of(const Vec3& p) const;
  void set(size_t cell, float z) { dtm_.z[cell] = z; }

 private:
  Dtm dtm_;
  double min_x_, max_y_, cell_;
};

// Why the DTM cannot give the parcel its terrain: the first vertex outside
// the grid, or "" when it covers the parcel.
std::string dtm_gap(const Dtm& dtm, const Parcel& parcel, const std::string& layer_source);

// Throws InputError naming the DTM file and the first parcel with a vertex
// outside the grid.
void check_dtm_covers(const Dtm& dtm, const ParcelLayer& parcels);

}  // namespace c3d
