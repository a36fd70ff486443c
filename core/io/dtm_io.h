#pragma once
// Digital terrain models: any GDAL raster, or a grid built from ground points.
// NoData holes (typically under buildings) are always filled, so that walls can
// be extruded down to the terrain everywhere.
#include <atomic>
#include <functional>
#include <future>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "core/gdal_dataset.h"
#include "core/io/dtm_fill.h"
#include "core/types.h"

namespace c3d {

// The most cells a DTM may have on this machine: kMaxDtmCells, or fewer where
// half the physical memory holds fewer (core/io/read_limits.h).
size_t dtm_cell_budget();

// Band 1 of any raster GDAL opens, NoData filled as DtmSource fills it (so
// the cells equal DtmSource's windows). Throws InputError on unreadable,
// rotated or all-NoData rasters, and on a raster of more than max_cells cells
// (checked before anything is allocated).
Dtm read_dtm(const std::string& path, size_t max_cells = dtm_cell_budget());
// read_dtm's header checks alone: extent, cells and CRS, no cell read (z empty).
Dtm read_dtm_header(const std::string& path);

// A GDAL raster DTM opened once (read_dtm's checks) and read a window at a
// time, so that no more than a window and a few filled tiles are held however
// large the raster. NoData is filled on a fixed grid of tiles of the raster:
// tile (i, j) is cells [i S, (i+1) S) x [j S, (j+1) S), S = kFillTileCells,
// filled from itself and kFillMarginCells around it (GDALFillNodata searching
// no farther than the margin, then the nearest valid cell there; a tile with
// no valid cell in that reach takes FarTerrain's heights), so a cell's height
// depends on the raster alone, never on the windows asked for, and filling
// costs a bounded amount per cell. A raster within one tile is filled whole. A window's cells and lookups equal
// read_dtm's grid's (Dtm::win_*). Thread-safe.
class DtmSource {
 public:
  explicit DtmSource(const std::string& path, size_t max_cells = dtm_cell_budget());
  ~DtmSource();
  // Extent, cells, CRS and NoData share of the whole raster; z empty.
  const Dtm& header() const { return header_; }
  size_t nodata_cells() const { return nodata_cells_; }
  // The cells covering the box, kWindowMarginCells more around, clipped to the
  // raster. Throws InputError when the window has more than max_cells cells.
  Dtm window(double min_x, double min_y, double max_x, double max_y) const;
  // All cells (read_dtm), assembled a tile at a time.
  Dtm whole() const;
  // How many valid (not NoData) cells' heights pick picks (a pass over the
  // raster's blocks), and the first such height in row order.
  size_t count_cells(const std::function<bool(float)>& pick, float* first) const;
  // The most cells one tile's fill has held (its tile and margin): what
  // filling costs, whatever the raster's size.
  size_t peak_fill_cells() const { return peak_fill_cells_; }

  // Bilinear lookups read the cell beyond; one more for safety.
  static constexpr int kWindowMarginCells = 2;
  // 4 MB of filled heights a tile: small next to a chunk's points, large
  // enough that a chunk's window touches few tiles.
  static constexpr int kFillTileCells = 1024;
  // The fill's reach beyond its tile, and the inverse-distance search's: a
  // hole up to 2 x 256 cells wide (256 m at 1 m cells, 128 m at AHN's 0.5 m) is
  // filled from its rims; a wider one can show a seam at a tile's edge.
  static constexpr int kFillMarginCells = 256;

 private:
  using Tile = std::vector<float>;  // a tile's filled cells, row-major
  std::shared_ptr<const Tile> tile(int ti, int tj) const;
  std::shared_ptr<const Tile> fill_tile(int ti, int tj) const;
  void copy_cells(int c0, int r0, int nx, int ny, std::vector<float>& out) const;
  void note_far_tile(int x0, int x1, int y0, int y1) const;

  size_t max_cells_;
  Dtm header_;
  size_t nodata_cells_ = 0;
  FarTerrain far_;  // heights beyond the fill's reach
  mutable std::once_flag far_noted_;
  GdalDataset ds_;
  mutable std::mutex read_;  // GDAL datasets are not thread-safe
  // The tiles filled last, most recent first (a future while one is filled).
  mutable std::mutex cache_mutex_;
  mutable std::list<std::pair<size_t, std::shared_future<std::shared_ptr<const Tile>>>> cache_;
  mutable std::atomic<size_t> peak_fill_cells_{0};
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
