#include "core/geometry/label_grid.h"

#include <gdal_alg.h>
#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include <stdexcept>

#include "core/gdal_dataset.h"

namespace c3d {
namespace {

GdalDataset create(const char* driver, int nx, int ny, GDALDataType type) {
  register_gdal_drivers();
  GDALDriver* d = GetGDALDriverManager()->GetDriverByName(driver);
  if (!d) throw std::runtime_error(std::string("GDAL has no ") + driver + " driver");
  return GdalDataset(d->Create("", nx, ny, nx > 0 ? 1 : 0, type, nullptr));
}

Ring2 ring_of(const OGRLinearRing& r) {
  Ring2 out;
  for (int i = 0; i + 1 < r.getNumPoints(); ++i) out.emplace_back(r.getX(i), r.getY(i));  // last repeats the first
  return out;
}

}  // namespace

std::vector<MultiPolygon2> polygonize(const LabelGrid& grid, size_t label_count) {
  std::vector<MultiPolygon2> out(label_count);
  if (grid.nx <= 0 || grid.ny <= 0) return out;
  GdalDataset raster = create("MEM", grid.nx, grid.ny, GDT_Int32);
  double transform[6] = {grid.origin.x(), grid.cell, 0, grid.origin.y(), 0, grid.cell};  // rows go up in y
  raster->SetGeoTransform(transform);
  GDALRasterBand* band = raster->GetRasterBand(1);
  if (band->RasterIO(GF_Write, 0, 0, grid.nx, grid.ny, const_cast<int*>(grid.labels.data()), grid.nx, grid.ny,
                     GDT_Int32, 0, 0) != CE_None)
    throw std::runtime_error("label grid: GDAL could not write the memory raster");
  GdalDataset vector = create("Memory", 0, 0, GDT_Unknown);
  OGRLayer* layer = vector->CreateLayer("regions", nullptr, wkbPolygon, nullptr);
  OGRFieldDefn field("label", OFTInteger);
  layer->CreateField(&field);
  if (GDALPolygonize(band, nullptr, layer, 0, nullptr, nullptr, nullptr) != CE_None)
    throw std::runtime_error("label grid: GDAL polygonize failed");
  layer->ResetReading();
  for (auto& feature : *layer) {
    const int label = feature->GetFieldAsInteger(0);
    const OGRGeometry* g = feature->GetGeometryRef();
    if (label < 0 || size_t(label) >= label_count || !g || wkbFlatten(g->getGeometryType()) != wkbPolygon) continue;
    const OGRPolygon* p = g->toPolygon();
    Polygon2 poly{ring_of(*p->getExteriorRing()), {}};
    for (int h = 0; h < p->getNumInteriorRings(); ++h) poly.holes.push_back(ring_of(*p->getInteriorRing(h)));
    out[size_t(label)].push_back(std::move(poly));
  }
  return out;
}

}  // namespace c3d
