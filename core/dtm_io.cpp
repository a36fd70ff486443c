#include "core/dtm_io.h"

#include <gdal_alg.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <memory>
#include <sstream>

#include "core/error.h"

namespace c3d {
namespace {

struct DatasetCloser {
  void operator()(GDALDataset* d) const { GDALClose(d); }
};
using Dataset = std::unique_ptr<GDALDataset, DatasetCloser>;

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

// Fills NaN cells of dtm.z: inverse-distance interpolation by GDALFillNodata on
// an in-memory copy, then nearest valid for whatever is left.
void fill_holes(Dtm& dtm) {
  const size_t cells = dtm.z.size();
  size_t holes = std::count_if(dtm.z.begin(), dtm.z.end(), [](float v) { return std::isnan(v); });
  dtm.nodata_share = cells ? double(holes) / double(cells) : 0.0;
  if (holes == 0) return;
  if (holes == cells) throw InputError(dtm.source, "DTM has no valid height (all cells NoData)");
  GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
  Dataset ds(mem->Create("", dtm.nx, dtm.ny, 1, GDT_Float32, nullptr));
  GDALRasterBand* band = ds->GetRasterBand(1);
  constexpr float kNoData = -3.4e38f;
  std::vector<float> work = dtm.z;
  for (float& v : work)
    if (std::isnan(v)) v = kNoData;
  band->SetNoDataValue(kNoData);
  if (band->RasterIO(GF_Write, 0, 0, dtm.nx, dtm.ny, work.data(), dtm.nx, dtm.ny, GDT_Float32, 0,
                     0) != CE_None)
    throw InputError(dtm.source, "cannot fill NoData (in-memory raster write failed)");
  double max_dist = std::max(dtm.nx, dtm.ny);
  GDALFillNodata(band, nullptr, max_dist, 0, 0, nullptr, nullptr, nullptr);
  if (band->RasterIO(GF_Read, 0, 0, dtm.nx, dtm.ny, work.data(), dtm.nx, dtm.ny, GDT_Float32, 0,
                     0) != CE_None)
    throw InputError(dtm.source, "cannot fill NoData (in-memory raster read failed)");
  std::vector<char> valid(cells);
  for (size_t i = 0; i < cells; ++i) {
    valid[i] = work[i] != kNoData && std::isfinite(work[i]);
    dtm.z[i] = work[i];
  }
  fill_nearest(dtm.z, valid, dtm.nx, dtm.ny);
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

}  // namespace

Dtm read_dtm(const std::string& path) {
  static const bool registered = (GDALAllRegister(), true);  // callers need not remember
  (void)registered;
  CPLPushErrorHandler(CPLQuietErrorHandler);
  Dataset ds(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
  CPLPopErrorHandler();
  if (!ds) throw InputError(path, "not a raster GDAL can read (" + std::string(CPLGetLastErrorMsg()) + ")");
  if (ds->GetRasterCount() < 1) throw InputError(path, "raster has no band");
  Dtm dtm;
  dtm.source = path;
  dtm.crs_wkt = crs_of(*ds);
  double gt[6];
  if (ds->GetGeoTransform(gt) != CE_None) throw InputError(path, "raster has no geotransform");
  if (gt[2] != 0 || gt[4] != 0) throw InputError(path, "rotated rasters are not supported");
  dtm.nx = ds->GetRasterXSize();
  dtm.ny = ds->GetRasterYSize();
  dtm.dx = gt[1];
  dtm.dy = gt[5];
  dtm.x0 = gt[0] + 0.5 * gt[1];
  dtm.y0 = gt[3] + 0.5 * gt[5];
  dtm.z.resize(size_t(dtm.nx) * dtm.ny);
  GDALRasterBand* band = ds->GetRasterBand(1);
  if (band->RasterIO(GF_Read, 0, 0, dtm.nx, dtm.ny, dtm.z.data(), dtm.nx, dtm.ny, GDT_Float32, 0,
                     0) != CE_None)
    throw InputError(path, "cannot read band 1: " + std::string(CPLGetLastErrorMsg()));
  int has_nodata = 0;
  double nodata = band->GetNoDataValue(&has_nodata);
  const float nodata_f = float(nodata);
  for (float& v : dtm.z)
    if ((has_nodata && (v == nodata_f || (std::isnan(nodata) && std::isnan(v)))) ||
        !std::isfinite(v))
      v = std::nanf("");
  fill_holes(dtm);
  return dtm;
}

Dtm dtm_from_points(const std::vector<Vec3>& ground, const std::string& crs_wkt, double cell_m,
                    DtmCell stat, const std::string& source) {
  static const bool registered = (GDALAllRegister(), true);  // callers need not remember
  (void)registered;
  if (ground.empty()) throw InputError(source, "no ground points to build a DTM from");
  if (!(cell_m > 0)) throw InputError(source, "DTM cell size must be positive");
  double minx = ground[0].x(), maxx = minx, miny = ground[0].y(), maxy = miny;
  for (const Vec3& p : ground) {
    minx = std::min(minx, p.x()), maxx = std::max(maxx, p.x());
    miny = std::min(miny, p.y()), maxy = std::max(maxy, p.y());
  }
  Dtm dtm;
  dtm.source = source;
  dtm.crs_wkt = crs_wkt;
  dtm.dx = cell_m;
  dtm.dy = -cell_m;  // north-up like a GeoTIFF
  dtm.nx = int(std::floor((maxx - minx) / cell_m)) + 1;
  dtm.ny = int(std::floor((maxy - miny) / cell_m)) + 1;
  dtm.x0 = minx + 0.5 * cell_m;
  dtm.y0 = maxy - 0.5 * cell_m;
  const size_t cells = size_t(dtm.nx) * dtm.ny;
  dtm.z.assign(cells, std::nanf(""));
  std::vector<double> sum(stat == DtmCell::Mean ? cells : 0);
  std::vector<int> count(stat == DtmCell::Mean ? cells : 0);
  for (const Vec3& p : ground) {
    int i = std::min(dtm.nx - 1, int((p.x() - minx) / cell_m));
    int j = std::min(dtm.ny - 1, int((maxy - p.y()) / cell_m));
    size_t k = size_t(j) * dtm.nx + i;
    if (stat == DtmCell::Mean) {
      sum[k] += p.z(), ++count[k];
    } else if (std::isnan(dtm.z[k]) || p.z() < dtm.z[k]) {
      dtm.z[k] = float(p.z());
    }
  }
  if (stat == DtmCell::Mean)
    for (size_t k = 0; k < cells; ++k)
      if (count[k]) dtm.z[k] = float(sum[k] / count[k]);
  fill_holes(dtm);
  return dtm;
}

void check_dtm_covers(const Dtm& dtm, const ParcelLayer& parcels) {
  auto check_ring = [&](const Parcel& parcel, const Ring2& ring) {
    for (const Vec2& v : ring) {
      if (dtm.covers(v.x(), v.y())) continue;
      std::ostringstream msg;
      msg.precision(3);
      msg << std::fixed << "does not cover parcel " << parcel.id << " (record " << parcel.index
          << " of " << parcels.source << "): vertex (" << v.x() << ", " << v.y()
          << ") lies outside the DTM extent x " << dtm.x0 - 0.5 * dtm.dx << ".."
          << dtm.x0 + (dtm.nx - 0.5) * dtm.dx << ", y " << dtm.y0 + (dtm.ny - 0.5) * dtm.dy << ".."
          << dtm.y0 - 0.5 * dtm.dy;
      throw InputError(dtm.source, msg.str());
    }
  };
  for (const Parcel& p : parcels.parcels)
    for (const Polygon2& poly : p.shape) check_ring(p, poly.outer);
}

}  // namespace c3d
