#include "core/io/dtm_io.h"

#include <gdal_alg.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <future>
#include <memory>
#include <mutex>
#include <sstream>

#include "core/error.h"
#include "core/gdal_dataset.h"
#include "core/io/dtm_fill.h"
#include "core/io/read_limits.h"
#include "core/log.h"

namespace c3d {
namespace {

constexpr size_t kStripCells = size_t(1) << 22;  // cells read at once by a pass over the raster (16 MB)

std::string crs_of(const GDALDataset& ds) {
  const OGRSpatialReference* srs = ds.GetSpatialRef();
  if (!srs) return {};
  char* out = nullptr;
  const char* opts[] = {"FORMAT=WKT2_2019", nullptr};  // compound CRS need WKT2
  srs->exportToWkt(&out, opts);
  std::string wkt = out ? out : "";
  CPLFree(out);
  return wkt;
}

// A grid larger than the budget is refused before anything is allocated.
void check_grid_size(const std::string& source, double nx, double ny, size_t max_cells,
                     const std::string& what) {
  if (nx >= 1 && ny >= 1 && nx * ny <= double(max_cells)) return;
  std::ostringstream s;
  s.precision(0);
  s << std::fixed << what << " " << nx << " x " << ny << " cells, more than the " << max_cells
    << " a DTM may have here (" << kDtmBytesPerCell
    << " bytes per cell while NoData is filled); crop it to the parcels first, e.g. "
       "`gdal_translate -projwin ...`";
  throw InputError(source, s.str());
}

// The geotransform must be finite, not rotated, with cells of non-zero size,
// and the raster's corners within kMaxAbsCoordinate.
void check_geotransform(const std::string& path, const double gt[6], int nx, int ny) {
  for (int i = 0; i < 6; ++i)
    if (!std::isfinite(gt[i])) throw InputError(path, "geotransform holds NaN/inf");
  if (gt[2] != 0 || gt[4] != 0) throw InputError(path, "rotated rasters are not supported");
  if (gt[1] == 0 || gt[5] == 0) throw InputError(path, "geotransform has cells of size 0");
  const double x1 = gt[0] + nx * gt[1], y1 = gt[3] + ny * gt[5];
  for (double v : {gt[0], gt[3], x1, y1})
    if (!coordinate_ok(v))
      throw InputError(path, "raster extent reaches " + std::to_string(v) +
                                 ", beyond +-1e17 (a damaged geotransform)");
}

}  // namespace

size_t dtm_cell_budget() {
  const size_t memory = physical_memory_bytes();
  const size_t by_memory = memory ? memory / 2 / kDtmBytesPerCell : kMaxDtmCells;
  return std::min(kMaxDtmCells, by_memory);
}

namespace {

// The raster opened and its header checked: the Dtm's geometry and CRS, z empty.
GdalDataset open_dtm(const std::string& path, Dtm& dtm) {
  register_gdal_drivers();
  CPLPushErrorHandler(CPLQuietErrorHandler);
  GdalDataset ds(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
  CPLPopErrorHandler();
  if (!ds) throw InputError(path, "not a raster GDAL can read (" + std::string(CPLGetLastErrorMsg()) + ")");
  if (ds->GetRasterCount() < 1) throw InputError(path, "raster has no band");
  dtm.source = path;
  dtm.crs_wkt = crs_of(*ds);
  double gt[6];
  if (ds->GetGeoTransform(gt) != CE_None) throw InputError(path, "raster has no geotransform");
  dtm.nx = ds->GetRasterXSize();
  dtm.ny = ds->GetRasterYSize();
  check_geotransform(path, gt, dtm.nx, dtm.ny);
  dtm.dx = gt[1];
  dtm.dy = gt[5];
  dtm.x0 = gt[0] + 0.5 * gt[1];
  dtm.y0 = gt[3] + 0.5 * gt[5];
  return ds;
}

// Cells [x, x + w) x [y, y + h) of band 1 into out, NoData and non-finite
// heights as NaN.
void read_cells(GDALDataset& ds, const std::string& path, int x, int y, int w, int h, std::vector<float>& out) {
  out.resize(size_t(w) * size_t(h));
  GDALRasterBand* band = ds.GetRasterBand(1);
  if (band->RasterIO(GF_Read, x, y, w, h, out.data(), w, h, GDT_Float32, 0, 0) != CE_None)
    throw InputError(path, "cannot read band 1: " + std::string(CPLGetLastErrorMsg()));
  int has_nodata = 0;
  double nodata = band->GetNoDataValue(&has_nodata);
  // GDAL clamps a Float64 raster's values into float range; the NoData value alike.
  const float nodata_f = float(std::clamp(nodata, double(-FLT_MAX), double(FLT_MAX)));
  for (float& v : out)
    if ((has_nodata && (v == nodata_f || (std::isnan(nodata) && std::isnan(v)))) || !std::isfinite(v))
      v = std::nanf("");
}

// Calls visit(z, y) for every row-major run of rows of the raster from row y,
// a strip of blocks at a time: only a strip is ever held.
template <class Visit>
void for_each_strip(GDALDataset& ds, const std::string& path, Visit visit) {
  int bx = 0, by = 0;
  ds.GetRasterBand(1)->GetBlockSize(&bx, &by);
  const int nx = ds.GetRasterXSize(), ny = ds.GetRasterYSize();
  const int rows = std::max(1, std::min(by, int(kStripCells / std::max(1, nx))));
  std::vector<float> strip;
  for (int y = 0; y < ny; y += rows) {
    read_cells(ds, path, 0, y, nx, std::min(rows, ny - y), strip);
    ds.GetRasterBand(1)->FlushCache();  // else GDAL's block cache keeps up to 5 % of memory
    visit(strip, y);
  }
}

}  // namespace

Dtm read_dtm(const std::string& path, size_t max_cells) {
  {
    Dtm header;
    open_dtm(path, header);
    check_grid_size(path, header.nx, header.ny, max_cells, "raster of");
  }
  return DtmSource(path, max_cells).whole();
}

namespace {

// A chunk's window (a few hundred metres) touches at most 2 x 2 tiles, and
// the next chunk (Hilbert order) lies beside it: four stay filled (16 MB).
constexpr size_t kCachedTiles = 4;

bool has_valid(const std::vector<float>& z) {
  return std::any_of(z.begin(), z.end(), [](float v) { return !std::isnan(v); });
}

}  // namespace

Dtm read_dtm_header(const std::string& path) {
  Dtm dtm;
  open_dtm(path, dtm);
  return dtm;
}

DtmSource::DtmSource(const std::string& path, size_t max_cells) : max_cells_(max_cells) {
  ds_ = open_dtm(path, header_);
  far_ = FarTerrain(header_.nx, header_.ny);
  for_each_strip(*ds_, path, [&](const std::vector<float>& z, int y) {
    nodata_cells_ += size_t(std::count_if(z.begin(), z.end(), [](float v) { return std::isnan(v); }));
    far_.add_rows(z, y);
  });
  const size_t cells = size_t(header_.nx) * size_t(header_.ny);
  if (!far_.finish()) throw InputError(path, "DTM has no valid height (all cells NoData)");
  header_.nodata_share = double(nodata_cells_) / double(cells);
  if (nodata_cells_ > 0 && (header_.nx > kFillTileCells || header_.ny > kFillTileCells))
    log::info(log::format("%s: NoData cells, filled in tiles of %d cells and %d around", path.c_str(),
                          kFillTileCells, kFillMarginCells));
}

DtmSource::~DtmSource() = default;

// Tile (ti, tj) filled from itself and its margin (clipped to the raster);
// a raster within one tile is filled whole, as one grid. A tile with no
// valid height within its margin is beyond the fill's reach: FarTerrain's.
std::shared_ptr<const DtmSource::Tile> DtmSource::fill_tile(int ti, int tj) const {
  const int nx = header_.nx, ny = header_.ny;
  const int x0 = ti * kFillTileCells, y0 = tj * kFillTileCells;
  const int x1 = std::min(nx, x0 + kFillTileCells), y1 = std::min(ny, y0 + kFillTileCells);
  const bool one_tile = nx <= kFillTileCells && ny <= kFillTileCells;
  const int gx0 = std::max(0, x0 - kFillMarginCells), gy0 = std::max(0, y0 - kFillMarginCells);
  const int gx1 = std::min(nx, x1 + kFillMarginCells), gy1 = std::min(ny, y1 + kFillMarginCells);
  Dtm grown = header_;
  grown.nx = gx1 - gx0, grown.ny = gy1 - gy0;
  const size_t held = size_t(grown.nx) * size_t(grown.ny);
  {
    std::lock_guard<std::mutex> lock(read_);
    read_cells(*ds_, header_.source, gx0, gy0, grown.nx, grown.ny, grown.z);
    ds_->GetRasterBand(1)->FlushCache();
  }
  size_t peak = peak_fill_cells_;
  while (held > peak && !peak_fill_cells_.compare_exchange_weak(peak, held)) {
  }
  auto tile = std::make_shared<Tile>(size_t(x1 - x0) * size_t(y1 - y0));
  if (!has_valid(grown.z)) {
    note_far_tile(x0, x1, y0, y1);
    for (int v = y0; v < y1; ++v)
      for (int u = x0; u < x1; ++u) (*tile)[size_t(v - y0) * (x1 - x0) + (u - x0)] = far_.height(u, v);
    return tile;
  }
  FillTile limits{kFillMarginCells, x0 - gx0, y0 - gy0, x1 - gx0, y1 - gy0, gx0 > 0, gy0 > 0, gx1 < nx, gy1 < ny};
  fill_holes(grown, one_tile ? nullptr : &limits);
  for (int v = y0; v < y1; ++v)
    std::copy_n(grown.z.begin() + (size_t(v - gy0) * grown.nx + (x0 - gx0)), x1 - x0,
                tile->begin() + size_t(v - y0) * (x1 - x0));
  return tile;
}

// Once per raster: its terrain is extrapolated far, which a user should know.
void DtmSource::note_far_tile(int x0, int x1, int y0, int y1) const {
  std::call_once(far_noted_, [&] {
    log::warn(log::format("%s: cells %d..%d x %d..%d (and maybe others) have no valid height within %d cells: "
                          "they take the mean height of the nearest %d x %d cells with terrain",
                          header_.source.c_str(), x0, x1 - 1, y0, y1 - 1, kFillMarginCells,
                          FarTerrain::kBlockCells, FarTerrain::kBlockCells));
  });
}

// The tile from the cache, or filled once (other threads asking meanwhile wait for it).
std::shared_ptr<const DtmSource::Tile> DtmSource::tile(int ti, int tj) const {
  const size_t key = size_t(tj) * size_t(header_.nx / kFillTileCells + 1) + size_t(ti);
  std::promise<std::shared_ptr<const Tile>> filling;
  std::shared_future<std::shared_ptr<const Tile>> ready, mine;
  {
    std::lock_guard<std::mutex> lock(cache_mutex_);
    auto hit = std::find_if(cache_.begin(), cache_.end(), [&](const auto& e) { return e.first == key; });
    if (hit != cache_.end()) {
      cache_.splice(cache_.begin(), cache_, hit);
      ready = hit->second;
    } else {
      mine = filling.get_future().share();
      cache_.emplace_front(key, mine);
      if (cache_.size() > kCachedTiles) cache_.pop_back();
    }
  }
  if (ready.valid()) return ready.get();  // filled, or being filled by another thread
  try {
    filling.set_value(fill_tile(ti, tj));
  } catch (...) {
    filling.set_exception(std::current_exception());
  }
  return mine.get();
}

// Cells [c0, c0 + w) x [r0, r0 + h) into out: read as they are, or from the
// filled tiles they lie in.
void DtmSource::copy_cells(int c0, int r0, int w, int h, std::vector<float>& out) const {
  if (nodata_cells_ == 0) {
    std::lock_guard<std::mutex> lock(read_);
    read_cells(*ds_, header_.source, c0, r0, w, h, out);
    ds_->GetRasterBand(1)->FlushCache();  // the window is all that stays
    return;
  }
  out.resize(size_t(w) * size_t(h));
  for (int tj = r0 / kFillTileCells; tj <= (r0 + h - 1) / kFillTileCells; ++tj)
    for (int ti = c0 / kFillTileCells; ti <= (c0 + w - 1) / kFillTileCells; ++ti) {
      const std::shared_ptr<const Tile> t = tile(ti, tj);
      const int tx0 = ti * kFillTileCells, ty0 = tj * kFillTileCells;
      const int tw = std::min(header_.nx, tx0 + kFillTileCells) - tx0;
      const int x0 = std::max(c0, tx0), x1 = std::min(c0 + w, tx0 + tw);
      const int y0 = std::max(r0, ty0), y1 = std::min({r0 + h, ty0 + kFillTileCells, header_.ny});
      for (int v = y0; v < y1; ++v)
        std::copy_n(t->begin() + (size_t(v - ty0) * tw + (x0 - tx0)), x1 - x0,
                    out.begin() + (size_t(v - r0) * w + (x0 - c0)));
    }
}

Dtm DtmSource::window(double min_x, double min_y, double max_x, double max_y) const {
  Dtm w = header_;
  // The cells whose centres are nearest the box's corners, kWindowMarginCells around.
  auto col = [&](double x) { return int(std::floor((x - w.x0) / w.dx + 0.5)); };
  auto row = [&](double y) { return int(std::floor((y - w.y0) / w.dy + 0.5)); };
  const int c0 = std::max(0, std::min(col(min_x), col(max_x)) - kWindowMarginCells);
  const int c1 = std::min(w.nx - 1, std::max(col(min_x), col(max_x)) + kWindowMarginCells);
  const int r0 = std::max(0, std::min(row(min_y), row(max_y)) - kWindowMarginCells);
  const int r1 = std::min(w.ny - 1, std::max(row(min_y), row(max_y)) + kWindowMarginCells);
  w.win_x = c0, w.win_y = r0;
  w.win_nx = std::max(0, c1 - c0 + 1), w.win_ny = std::max(0, r1 - r0 + 1);
  if (w.win_nx == 0 || w.win_ny == 0) {  // the box misses the raster: a window of no cell of it
    w.win_x = w.win_y = -1, w.win_nx = w.win_ny = 1, w.z.assign(1, std::nanf(""));
    return w;
  }
  check_grid_size(w.source, w.win_nx, w.win_ny, max_cells_, "a window of");
  copy_cells(c0, r0, w.win_nx, w.win_ny, w.z);
  return w;
}

Dtm DtmSource::whole() const {
  Dtm d = header_;
  copy_cells(0, 0, d.nx, d.ny, d.z);
  return d;
}

size_t DtmSource::count_cells(const std::function<bool(float)>& pick, float* first) const {
  size_t n = 0;
  std::lock_guard<std::mutex> lock(read_);
  for_each_strip(*ds_, header_.source, [&](const std::vector<float>& z, int) {
    for (float v : z)
      if (!std::isnan(v) && pick(v) && n++ == 0 && first) *first = v;
  });
  return n;
}

GroundDtmBuilder::GroundDtmBuilder(double min_x, double min_y, double max_x, double max_y,
                                   const std::string& crs_wkt, double cell_m, const std::string& source)
    : min_x_(min_x), max_y_(max_y), cell_(cell_m) {
  register_gdal_drivers();
  if (!(cell_m > 0)) throw InputError(source, "DTM cell size must be positive");
  dtm_.source = source;
  dtm_.crs_wkt = crs_wkt;
  dtm_.dx = cell_m;
  dtm_.dy = -cell_m;  // north-up like a GeoTIFF
  const double nx = std::floor((max_x - min_x) / cell_m) + 1, ny = std::floor((max_y - min_y) / cell_m) + 1;
  check_grid_size(source, nx, ny, dtm_cell_budget(), "the ground points span");
  dtm_.nx = int(nx);
  dtm_.ny = int(ny);
  dtm_.x0 = min_x + 0.5 * cell_m;
  dtm_.y0 = max_y - 0.5 * cell_m;
  dtm_.z.assign(size_t(dtm_.nx) * dtm_.ny, std::nanf(""));
}

size_t GroundDtmBuilder::cell_of(const Vec3& p) const {
  const int i = std::min(dtm_.nx - 1, int((p.x() - min_x_) / cell_));
  const int j = std::min(dtm_.ny - 1, int((max_y_ - p.y()) / cell_));
  return size_t(j) * dtm_.nx + i;
}

void GroundDtmBuilder::add(const std::vector<Vec3>& ground) {
  for (const Vec3& p : ground) {
    float& z = dtm_.z[cell_of(p)];
    if (std::isnan(z) || p.z() < z) z = float(p.z());
  }
}

Dtm GroundDtmBuilder::finish() {
  fill_holes(dtm_);
  return std::move(dtm_);
}

Dtm dtm_from_points(const std::vector<Vec3>& ground, const std::string& crs_wkt, double cell_m,
                    DtmCell stat, const std::string& source) {
  if (ground.empty()) throw InputError(source, "no ground points to build a DTM from");
  double minx = ground[0].x(), maxx = minx, miny = ground[0].y(), maxy = miny;
  for (const Vec3& p : ground) {
    minx = std::min(minx, p.x()), maxx = std::max(maxx, p.x());
    miny = std::min(miny, p.y()), maxy = std::max(maxy, p.y());
  }
  GroundDtmBuilder grid(minx, miny, maxx, maxy, crs_wkt, cell_m, source);
  if (stat == DtmCell::Min) {
    grid.add(ground);
    return grid.finish();
  }
  std::vector<double> sum(grid.cells());
  std::vector<int> count(grid.cells());
  for (const Vec3& p : ground) {
    const size_t k = grid.cell_of(p);
    sum[k] += p.z(), ++count[k];
  }
  for (size_t k = 0; k < sum.size(); ++k)
    if (count[k]) grid.set(k, float(sum[k] / count[k]));
  return grid.finish();
}

std::string dtm_gap(const Dtm& dtm, const Parcel& parcel, const std::string& layer_source) {
  for (const Polygon2& poly : parcel.shape)
    for (const Vec2& v : poly.outer) {
      if (dtm.covers(v.x(), v.y())) continue;
      std::ostringstream msg;
      msg.precision(3);
      msg << std::fixed << "does not cover parcel " << parcel.id << " (record " << parcel.index
          << " of " << layer_source << "): vertex (" << v.x() << ", " << v.y()
          << ") lies outside the DTM extent x " << dtm.x0 - 0.5 * dtm.dx << ".."
          << dtm.x0 + (dtm.nx - 0.5) * dtm.dx << ", y " << dtm.y0 + (dtm.ny - 0.5) * dtm.dy << ".."
          << dtm.y0 - 0.5 * dtm.dy;
      return msg.str();
    }
  return {};
}

void check_dtm_covers(const Dtm& dtm, const ParcelLayer& parcels) {
  for (const Parcel& p : parcels.parcels) {
    const std::string gap = dtm_gap(dtm, p, parcels.source);
    if (!gap.empty()) throw InputError(dtm.source, gap);
  }
}

}  // namespace c3d
