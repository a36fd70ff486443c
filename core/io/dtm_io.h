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

// Why the DTM cannot give the parcel its terrain: the first vertex outside
// the grid, or "" when it covers the parcel.
std::string dtm_gap(const Dtm& dtm, const Parcel& parcel, const std::string& layer_source);

// Throws InputError naming the DTM file and the first parcel with a vertex
// outside the grid.
void check_dtm_covers(const Dtm& dtm, const ParcelLayer& parcels);

}  // namespace c3d
