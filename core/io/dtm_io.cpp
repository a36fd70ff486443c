#include "core/io/dtm_io.h"

#include <gdal_alg.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <deque>
#include <memory>
#include <mutex>
#include <sstream>

#include <Eigen/Dense>

#include "core/error.h"
#include "core/gdal_dataset.h"
#include "core/io/read_limits.h"
#include "core/log.h"

namespace c3d {
namespace {

// Remaining holes take the value of the nearest valid cell (multi-source BFS,
// 8-connected): GDALFillNodata stops at its search distance.
void fill_nearest(std::vector<float>& z, const std::vector<char>& valid_in, int nx, int ny) {
  std::vector<char> valid = valid_in;
  std::deque<size_t> queue;
  for (size_t i = 0; i < z.size(); ++i)
    if (valid[i]) queue.push_back(i);
  while (!queue.empty()) {
    size_t i = queue.front();
    queue.pop_front();
    int x = int(i % nx), y = int(i / nx);
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        int u = x + dx, v = y + dy;
        if (u < 0 || v < 0 || u >= nx || v >= ny) continue;
        size_t j = size_t(v) * nx + u;
        if (valid[j]) continue;
        valid[j] = 1;
        z[j] = z[i];
        queue.push_back(j);
      }
  }
}

// GDALFillNodata's time grows with NoData cells x search distance: a 2 KB
// GeoTIFF of 18192 x 12 cells, all but a few NoData, took 26 s at the full
// distance. Past this much work (about 2 s) the distance shrinks (Cimahi's
// DTM needs 5e7) and fill_nearest fills what the shorter search leaves.
constexpr double kMaxFillWork = 4e8;
constexpr size_t kStripCells = size_t(1) << 22;  // cells read at once by a pass over the raster (16 MB)
constexpr int kMinFillSearch = 32;  // cells; never shorter than this

int fill_search_distance(const std::vector<float>& z, int nx, int ny, const std::string& source) {
  const double holes = double(std::count_if(z.begin(), z.end(), [](float v) { return std::isnan(v); }));
  const int full = std::max(nx, ny);
  if (holes * full <= kMaxFillWork) return full;
  const int shorter = std::max(kMinFillSearch, int(kMaxFillWork / holes));
  if (shorter >= full) return full;
  log::warn(log::format("%s: %.0f NoData cells; inverse-distance fill searches %d cells (not %d), "
                        "the nearest valid height beyond", source.c_str(), holes, shorter, full));
  return shorter;
}

// GDALFillNodata (inverse distance) on an in-memory copy of z, NaN being
// NoData; whatever it leaves takes the nearest valid cell.
void idw_fill(std::vector<float>& z, int nx, int ny, const std::string& source) {
  GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
  GdalDataset ds(mem->Create("", nx, ny, 1, GDT_Float32, nullptr));
  GDALRasterBand* band = ds->GetRasterBand(1);
  constexpr float kNoData = -3.4e38f;
  std::vector<float> work = z;
  for (float& v : work)
    if (std::isnan(v)) v = kNoData;
  band->SetNoDataValue(kNoData);
  if (band->RasterIO(GF_Write, 0, 0, nx, ny, work.data(), nx, ny, GDT_Float32, 0, 0) != CE_None)
    throw InputError(source, "cannot fill NoData (in-memory raster write failed)");
  // Its work rasters in memory too: by default GDAL writes them as GeoTIFFs in
  // the current directory, and a killed batch would leave them there.
  const char* const fill_options[] = {"TEMP_FILE_DRIVER=MEM", nullptr};
  GDALFillNodata(band, nullptr, fill_search_distance(z, nx, ny, source), 0, 0, const_cast<char**>(fill_options),
                 nullptr, nullptr);
  if (band->RasterIO(GF_Read, 0, 0, nx, ny, work.data(), nx, ny, GDT_Float32, 0, 0) != CE_None)
    throw InputError(source, "cannot fill NoData (in-memory raster read failed)");
  std::vector<char> valid(z.size());
  for (size_t i = 0; i < z.size(); ++i) {
    valid[i] = work[i] != kNoData && std::isfinite(work[i]);
    z[i] = work[i];
  }
  fill_nearest(z, valid, nx, ny);
}

// Under a building the terrain's slope and curvature run on, but an
// inverse-distance fill flattens them: it put detached houses' floors 1.5 cm
// (RMS) off, and the middle of a row of houses 5 cm. So each hole of building
// size is filled with a moving least-squares quadratic: at each cell, the
// quadratic fitted to the valid cells within kRing cells around the hole,
// weighted by their distance to that cell (Gaussian, kSurfaceScale_m), plus
// the inverse-distance fill of that surface's residuals on the ring, so the
// fill meets the ring's own heights. A ring the surface does not fit (walls,
// trees: RMS > kRingFitRms) keeps the plain fill.
constexpr int kRing = 2;
constexpr size_t kMaxSurfaceHole = 10000;  // cells; larger holes keep the plain fill
constexpr double kSurfaceScale_m = 6.0;
constexpr double kRingFitRms = 0.10;       // m

struct HoleRegion {
  std::vector<size_t> cells;
  int x0, y0, x1, y1;  // bounding box with the ring, clipped to the grid
};

// 4-connected NoData components of `hole`.
std::vector<HoleRegion> hole_components(const std::vector<char>& hole, int nx, int ny) {
  std::vector<HoleRegion> out;
  std::vector<char> seen(hole.size(), 0);
  for (size_t start = 0; start < hole.size(); ++start) {
    if (!hole[start] || seen[start]) continue;
    HoleRegion h{{start}, nx, ny, -1, -1};
    seen[start] = 1;
    for (size_t k = 0; k < h.cells.size(); ++k) {
      int x = int(h.cells[k] % nx), y = int(h.cells[k] / nx);
      h.x0 = std::min(h.x0, x), h.x1 = std::max(h.x1, x), h.y0 = std::min(h.y0, y), h.y1 = std::max(h.y1, y);
      const int step[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
      for (const auto& d : step) {
        int u = x + d[0], v = y + d[1];
        if (u < 0 || v < 0 || u >= nx || v >= ny) continue;
        size_t j = size_t(v) * nx + u;
        if (hole[j] && !seen[j]) seen[j] = 1, h.cells.push_back(j);
      }
    }
    h.x0 = std::max(0, h.x0 - kRing), h.y0 = std::max(0, h.y0 - kRing);
    h.x1 = std::min(nx - 1, h.x1 + kRing), h.y1 = std::min(ny - 1, h.y1 + kRing);
    out.push_back(std::move(h));
  }
  return out;
}

// The valid cells within kRing cells of the hole.
std::vector<size_t> ring_of(const HoleRegion& h, const std::vector<char>& hole, int nx) {
  std::vector<size_t> ring;
  int w = h.x1 - h.x0 + 1;
  std::vector<char> in_ring(size_t(w) * size_t(h.y1 - h.y0 + 1), 0);
  for (size_t c : h.cells) {
    int x = int(c % nx), y = int(c / nx);
    for (int v = std::max(h.y0, y - kRing); v <= std::min(h.y1, y + kRing); ++v)
      for (int u = std::max(h.x0, x - kRing); u <= std::min(h.x1, x + kRing); ++u) {
        size_t j = size_t(v) * nx + u, local = size_t(v - h.y0) * size_t(w) + size_t(u - h.x0);
        if (!hole[j] && !in_ring[local]) in_ring[local] = 1, ring.push_back(j);
      }
  }
  return ring;
}

// Moving least-squares quadratic through the ring cells, evaluated at cell
// (x, y); NaN where the weighted ring does not span both axes.
double mls_height(const std::vector<size_t>& ring, const std::vector<float>& z, int nx, double x, double y,
                  double scale_cells) {
  Eigen::Matrix<double, 6, 6> ata = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> atb = Eigen::Matrix<double, 6, 1>::Zero();
  for (size_t r : ring) {
    double u = double(r % nx) - x, v = double(r / nx) - y, d2 = (u * u + v * v) / (scale_cells * scale_cells);
    if (d2 > 9.0) continue;  // weight below 1e-4
    double w = std::exp(-d2);
    Eigen::Matrix<double, 6, 1> t;
    t << 1, u, v, u * u, u * v, v * v;
    ata += w * t * t.transpose();
    atb += w * z[r] * t;
  }
  Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt(ata);
  if (ldlt.info() != Eigen::Success || ldlt.rcond() < 1e-9) return std::nan("");
  return ldlt.solve(atb)(0);  // the constant term: the surface at (x, y)
}

void fill_with_surface(std::vector<float>& z, const std::vector<char>& hole, const HoleRegion& h, int nx,
                       double cell_m, const std::string& source) {
  if (h.cells.size() > kMaxSurfaceHole) return;
  std::vector<size_t> ring = ring_of(h, hole, nx);
  if (ring.size() < 12) return;
  double scale = std::max(2.0, kSurfaceScale_m / cell_m);
  auto surface = [&](size_t cell) { return mls_height(ring, z, nx, double(cell % nx), double(cell / nx), scale); };
  int w = h.x1 - h.x0 + 1, hgt = h.y1 - h.y0 + 1;
  auto local = [&](size_t cell) { return size_t(int(cell / nx) - h.y0) * w + size_t(int(cell % nx) - h.x0); };
  std::vector<float> residual(size_t(w) * size_t(hgt), std::nanf(""));
  double sq = 0;
  for (size_t r : ring) {
    double d = z[r] - surface(r);
    if (!std::isfinite(d)) return;
    sq += d * d;
    residual[local(r)] = float(d);
  }
  if (!(std::sqrt(sq / double(ring.size())) <= kRingFitRms)) return;
  std::vector<double> fitted(h.cells.size());
  for (size_t k = 0; k < h.cells.size(); ++k)
    if (!std::isfinite(fitted[k] = surface(h.cells[k]))) return;
  idw_fill(residual, w, hgt, source);
  for (size_t k = 0; k < h.cells.size(); ++k) z[h.cells[k]] = float(fitted[k] + residual[local(h.cells[k])]);
}

// Fills NaN cells of dtm.z: inverse-distance interpolation (GDALFillNodata),
// building-size holes with the terrain's trend (fill_with_surface).
void fill_holes(Dtm& dtm) {
  const size_t cells = dtm.z.size();
  size_t holes = std::count_if(dtm.z.begin(), dtm.z.end(), [](float v) { return std::isnan(v); });
  dtm.nodata_share = cells ? double(holes) / double(cells) : 0.0;
  if (holes == 0) return;
  if (holes == cells) throw InputError(dtm.source, "DTM has no valid height (all cells NoData)");
  std::vector<char> hole(cells);
  for (size_t i = 0; i < cells; ++i) hole[i] = std::isnan(dtm.z[i]);
  idw_fill(dtm.z, dtm.nx, dtm.ny, dtm.source);
  for (const auto& h : hole_components(hole, dtm.nx, dtm.ny))
    fill_with_surface(dtm.z, hole, h, dtm.nx, std::abs(dtm.dx), dtm.source);
}

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

// Calls visit(z) for every row-major run of rows of the raster, a strip of
// blocks at a time: only a strip is ever held.
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
    visit(strip);
  }
}

}  // namespace

Dtm read_dtm(const std::string& path, size_t max_cells) {
  Dtm dtm;
  GdalDataset ds = open_dtm(path, dtm);
  check_grid_size(path, dtm.nx, dtm.ny, max_cells, "raster of");
  read_cells(*ds, path, 0, 0, dtm.nx, dtm.ny, dtm.z);
  fill_holes(dtm);
  return dtm;
}

DtmSource::DtmSource(const std::string& path, size_t max_cells) : max_cells_(max_cells) {
  Dtm header;
  GdalDataset ds = open_dtm(path, header);
  bool holes = false;
  for_each_strip(*ds, path, [&](const std::vector<float>& z) {
    holes = holes || std::any_of(z.begin(), z.end(), [](float v) { return std::isnan(v); });
  });
  if (holes) {
    ds.reset();
    whole_ = read_dtm(path, max_cells);  // holes are filled from the whole raster
    header_ = whole_;
    header_.z.clear();
    header_.z.shrink_to_fit();
    log::info(path + ": NoData cells, read whole (their fill looks at the whole raster)");
  } else {
    header_ = std::move(header);
    ds_ = std::move(ds);
  }
}

DtmSource::~DtmSource() = default;

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
  if (!whole_.z.empty()) {
    w.z.resize(size_t(w.win_nx) * size_t(w.win_ny));
    for (int v = 0; v < w.win_ny; ++v)
      std::copy_n(whole_.z.begin() + (size_t(r0 + v) * whole_.nx + c0), w.win_nx, w.z.begin() + size_t(v) * w.win_nx);
    return w;
  }
  std::lock_guard<std::mutex> lock(read_);
  read_cells(*ds_, w.source, c0, r0, w.win_nx, w.win_ny, w.z);
  ds_->GetRasterBand(1)->FlushCache();  // the window is all that stays
  return w;
}

size_t DtmSource::count_cells(const std::function<bool(float)>& pick, float* first) const {
  size_t n = 0;
  auto visit = [&](const std::vector<float>& z) {
    for (float v : z)
      if (pick(v) && n++ == 0 && first) *first = v;
  };
  if (!whole_.z.empty()) {
    visit(whole_.z);
    return n;
  }
  std::lock_guard<std::mutex> lock(read_);
  for_each_strip(*ds_, header_.source, visit);
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
