#include "core/io/dtm_fill.h"

#include <gdal_alg.h>
#include <gdal_priv.h>

#include <algorithm>
#include <cmath>
#include <deque>

#include <Eigen/Dense>

#include "core/error.h"
#include "core/gdal_dataset.h"
#include "core/log.h"

namespace c3d {
namespace {

// Remaining holes take the value of the nearest valid cell (multi-source BFS,
// 8-connected): GDALFillNodata stops at its search distance. Only valid cells
// next to a hole start the search: the others would add nothing, and a queue
// of every cell of a grown DTM tile was 19 MB (the same order, so the same fill).
void fill_nearest(std::vector<float>& z, std::vector<char>& valid, int nx, int ny) {
  const auto borders_hole = [&](size_t i) {
    const int x = int(i % nx), y = int(i / nx);
    for (int v = std::max(0, y - 1); v <= std::min(ny - 1, y + 1); ++v)
      for (int u = std::max(0, x - 1); u <= std::min(nx - 1, x + 1); ++u)
        if (!valid[size_t(v) * nx + u]) return true;
    return false;
  };
  std::deque<size_t> queue;
  for (size_t i = 0; i < z.size(); ++i)
    if (valid[i] && borders_hole(i)) queue.push_back(i);
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

// GDALFillNodata's time grows with NoData cells x search distance where the
// holes are wide (small holes stop the search early): a 2 KB GeoTIFF of
// 18192 x 12 cells, all but a few NoData, took 26 s at the full distance, and
// 10^6 such cells take 0.08 s + 4.5 ns x cells x distance here. Past this
// much work (about 0.35 s) the distance shrinks (Cimahi's DTM needs 5.2e7 and
// keeps its full distance) and fill_nearest fills what the shorter search leaves.
constexpr double kMaxFillWork = 6e7;
constexpr int kMinFillSearch = 32;  // cells; never shorter than this

// A tile's search never reaches past its margin, and a shorter one is the
// tile's own affair (a sea tile would repeat it a thousand times): info, not warn.
int fill_search_distance(const std::vector<float>& z, int nx, int ny, const std::string& source,
                         const FillTile* tile) {
  const double holes = double(std::count_if(z.begin(), z.end(), [](float v) { return std::isnan(v); }));
  const int full = tile ? std::min(tile->max_search, std::max(nx, ny)) : std::max(nx, ny);
  if (holes * full <= kMaxFillWork) return full;
  const int shorter = std::max(kMinFillSearch, int(kMaxFillWork / holes));
  if (shorter >= full) return full;
  const std::string note = log::format("%s: %.0f NoData cells; inverse-distance fill searches %d cells (not %d), "
                                       "the nearest valid height beyond", source.c_str(), holes, shorter, full);
  tile ? log::info(note) : log::warn(note);
  return shorter;
}

// GDALFillNodata (inverse distance) on an in-memory copy of z, NaN being
// NoData; whatever it leaves takes the nearest valid cell.
void idw_fill(std::vector<float>& z, int nx, int ny, const std::string& source, const FillTile* tile = nullptr) {
  GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
  GdalDataset ds(mem->Create("", nx, ny, 1, GDT_Float32, nullptr));
  GDALRasterBand* band = ds->GetRasterBand(1);
  constexpr float kNoData = -3.4e38f;
  const int search = fill_search_distance(z, nx, ny, source, tile);
  for (float& v : z)  // z itself goes through the raster: no second copy of a tile
    if (std::isnan(v)) v = kNoData;
  band->SetNoDataValue(kNoData);
  if (band->RasterIO(GF_Write, 0, 0, nx, ny, z.data(), nx, ny, GDT_Float32, 0, 0) != CE_None)
    throw InputError(source, "cannot fill NoData (in-memory raster write failed)");
  // Its work rasters in memory too: by default GDAL writes them as GeoTIFFs in
  // the current directory, and a killed batch would leave them there.
  const char* const fill_options[] = {"TEMP_FILE_DRIVER=MEM", nullptr};
  GDALFillNodata(band, nullptr, search, 0, 0, const_cast<char**>(fill_options), nullptr, nullptr);
  if (band->RasterIO(GF_Read, 0, 0, nx, ny, z.data(), nx, ny, GDT_Float32, 0, 0) != CE_None)
    throw InputError(source, "cannot fill NoData (in-memory raster read failed)");
  std::vector<char> valid(z.size());
  for (size_t i = 0; i < z.size(); ++i) valid[i] = z[i] != kNoData && std::isfinite(z[i]);
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
  int hx0, hy0, hx1, hy1;  // bounding box of the hole's own cells
};

// 4-connected NoData components of `hole`.
std::vector<HoleRegion> hole_components(const std::vector<char>& hole, int nx, int ny) {
  std::vector<HoleRegion> out;
  std::vector<char> seen(hole.size(), 0);
  for (size_t start = 0; start < hole.size(); ++start) {
    if (!hole[start] || seen[start]) continue;
    HoleRegion h{{start}, nx, ny, -1, -1, 0, 0, 0, 0};
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
    h.hx0 = h.x0, h.hy0 = h.y0, h.hx1 = h.x1, h.hy1 = h.y1;
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

// Whether a tile's fill gives the hole its surface: the hole reaches the
// cells kept, and no cut side hides part of it.
bool surface_fill_here(const HoleRegion& h, const FillTile* tile, int nx, int ny) {
  if (!tile) return true;
  if (h.hx1 < tile->keep_x0 || h.hx0 >= tile->keep_x1 || h.hy1 < tile->keep_y0 || h.hy0 >= tile->keep_y1)
    return false;
  return !((tile->cut_left && h.hx0 == 0) || (tile->cut_top && h.hy0 == 0) ||
           (tile->cut_right && h.hx1 == nx - 1) || (tile->cut_bottom && h.hy1 == ny - 1));
}

}  // namespace

FarTerrain::FarTerrain(int nx, int ny)
    : nx_(nx), ny_(ny), bx_((nx + kBlockCells - 1) / kBlockCells), by_((ny + kBlockCells - 1) / kBlockCells),
      sum_(size_t(bx_) * size_t(by_), 0.0), count_(sum_.size(), 0) {}

void FarTerrain::add_rows(const std::vector<float>& z, int y0) {
  const int rows = int(z.size() / size_t(nx_));
  for (int v = 0; v < rows; ++v) {
    const size_t row = size_t((y0 + v) / kBlockCells) * size_t(bx_);
    for (int u = 0; u < nx_; ++u) {
      const float h = z[size_t(v) * nx_ + u];
      if (std::isnan(h)) continue;
      sum_[row + u / kBlockCells] += h;
      ++count_[row + u / kBlockCells];
    }
  }
}

bool FarTerrain::finish() {
  block_z_.assign(sum_.size(), 0.0f);
  std::vector<char> valid(sum_.size());
  for (size_t b = 0; b < sum_.size(); ++b)
    if ((valid[b] = count_[b] > 0)) block_z_[b] = float(sum_[b] / count_[b]);
  sum_ = {}, count_ = {};
  if (std::find(valid.begin(), valid.end(), 1) == valid.end()) return false;
  fill_nearest(block_z_, valid, bx_, by_);
  return true;
}

float FarTerrain::height(int x, int y) const {
  // Position in block units, 0 at the centre of block 0, clamped to the centres.
  const auto at = [](int cell, int blocks) {
    return std::clamp((cell + 0.5) / kBlockCells - 0.5, 0.0, double(blocks - 1));
  };
  const double u = at(x, bx_), v = at(y, by_);
  const int i = std::min(int(u), std::max(0, bx_ - 2)), j = std::min(int(v), std::max(0, by_ - 2));
  const int i1 = std::min(i + 1, bx_ - 1), j1 = std::min(j + 1, by_ - 1);
  const double fu = u - i, fv = v - j;
  const auto z = [&](int a, int b) { return double(block_z_[size_t(b) * bx_ + a]); };
  return float((1 - fv) * ((1 - fu) * z(i, j) + fu * z(i1, j)) + fv * ((1 - fu) * z(i, j1) + fu * z(i1, j1)));
}

// Inverse-distance interpolation (GDALFillNodata), building-size holes with
// the terrain's trend (fill_with_surface).
void fill_holes(Dtm& dtm, const FillTile* tile) {
  const size_t cells = dtm.z.size();
  size_t holes = std::count_if(dtm.z.begin(), dtm.z.end(), [](float v) { return std::isnan(v); });
  dtm.nodata_share = cells ? double(holes) / double(cells) : 0.0;
  if (holes == 0) return;
  if (holes == cells) throw InputError(dtm.source, "DTM has no valid height (all cells NoData)");
  std::vector<char> hole(cells);
  for (size_t i = 0; i < cells; ++i) hole[i] = std::isnan(dtm.z[i]);
  idw_fill(dtm.z, dtm.nx, dtm.ny, dtm.source, tile);
  for (const auto& h : hole_components(hole, dtm.nx, dtm.ny))
    if (surface_fill_here(h, tile, dtm.nx, dtm.ny))
      fill_with_surface(dtm.z, hole, h, dtm.nx, std::abs(dtm.dx), dtm.source);
}

}  // namespace c3d
