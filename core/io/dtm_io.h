#pragma once
// Digital terrain models: any GDAL raster, or a grid built from ground points.
// NoData holes (typically under buildings) are always filled, so that walls can
// be extruded down to the terrain everywhere.
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "core/gdal_dataset.h"
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

// A GDAL raster DTM opened once (read_dtm's checks) and read a window at a
// time, so that no more than a window is held however large the raster. A
// window's cells and lookups equal read_dtm's grid's (Dtm::win_*). A raster
// with NoData is read whole once (read_dtm): GDALFillNodata fills its holes
// from the whole raster, which a window cannot reproduce.
class DtmSource {
 public:
  explicit DtmSource(const std::string& path, size_t max_cells = dtm_cell_budget());
  ~DtmSource();
  // Extent, cells, CRS and NoData share of the whole raster; z empty.
  const Dtm& header() const { return header_; }
  bool windowed() const { return whole_.z.empty(); }
  // The cells covering the box, kWindowMarginCells more around, clipped to the
  // raster. Throws InputError when the window has more than max_cells cells.
  Dtm window(double min_x, double min_y, double max_x, double max_y) const;
  // How many cells' heights pick picks (a pass over the raster's blocks), and
  // the first such height in row order.
  size_t count_cells(const std::function<bool(float)>& pick, float* first) const;

  // Bilinear lookups read the cell beyond; one more for safety.
  static constexpr int kWindowMarginCells = 2;

 private:
  size_t max_cells_;
  Dtm header_;
  Dtm whole_;  // a raster with NoData, filled; else empty
  GdalDataset ds_;
  mutable std::mutex read_;  // GDAL datasets are not thread-safe
};

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
