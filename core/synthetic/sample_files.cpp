// The sample town on disk: parcels (GeoPackage or GeoJSON), the DTM GeoTIFF,
// the LAS cloud and truth.json.
#include <gdal_priv.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "core/gdal_dataset.h"
#include "core/geometry/geometry.h"
#include "core/io/point_io.h"
#include "core/synthetic/sample_town.h"

namespace c3d {

// ---- Files ----

namespace {

double r6(double x) { return std::round(x * 1e6) / 1e6; }

nlohmann::ordered_json building_json(const TruthBuilding& tb, const LocalFrame& frame) {
  const Building& m = tb.model;
  BuildingTotals t = totals(m);
  nlohmann::ordered_json j;
  j["building_id"] = m.id;
  j["roof_type"] = tb.roof_type;
  j["overhang_m"] = r6(tb.params.overhang);
  j["pitch_deg"] = r6(tb.params.layout == SampleLayout::Flat || tb.exact_areas ? 0.0 : tb.params.pitch_deg);
  if (tb.exact_areas) j["rise_m"] = r6(tb.params.rise);
  j["ground_level_m"] = r6(tb.ground_level);
  j["roof_area_m2"] = r6(t.roof);
  j["roof_plan_area_m2"] = r6(t.roof_plan);
  j["wall_area_m2"] = r6(t.wall);
  j["party_wall_area_m2"] = r6(t.party_wall);
  j["ground_area_m2"] = r6(t.ground);
  j["outer_ceiling_area_m2"] = r6(t.outer_ceiling);
  j["volume_m3"] = r6(m.volume);
  j["eave_height_m"] = r6(m.eave_height);
  j["wall_top_height_m"] = r6(tb.wall_top_height);
  j["ridge_height_m"] = r6(m.ridge_height);
  j["roof_planes"] = t.roof_planes;
  j["attached_to"] = tb.attached_to;
  auto planes = nlohmann::ordered_json::array();
  for (const auto& e : m.elements)
    if (e.type == ElementType::Roof)
      planes.push_back({{"area_m2", r6(e.area)}, {"plan_area_m2", r6(e.plan_area)},
                        {"slope_deg", r6(e.slope_deg)}, {"azimuth_deg", r6(e.azimuth_deg)},
                        {"points", e.support_points}});
  j["roof_plane_details"] = planes;
  auto fp = nlohmann::ordered_json::array();
  for (const auto& p : tb.footprint) {
    Vec2 w = frame.to_world(p);
    fp.push_back({r6(w.x()), r6(w.y())});
  }
  j["footprint"] = fp;
  if (!tb.openings.empty()) {  // world coordinates, as the footprint
    auto openings = nlohmann::ordered_json::array();
    for (const Opening& o : tb.openings) {
      auto corners = nlohmann::ordered_json::array();
      for (const Vec3& p : o.frame) {
        const Vec3 w = frame.to_world(p);
        corners.push_back({r6(w.x()), r6(w.y()), r6(w.z())});
      }
      openings.push_back({{"kind", o.kind},
                          {"frame", corners},
                          {"inward", {r6(o.inward.x()), r6(o.inward.y()), r6(o.inward.z())}},
                          {"depth_m", r6(o.depth)}});
    }
    j["openings"] = openings;
  }
  return j;
}

void write_parcels(const SampleTown& town, const std::string& path, ParcelFormat format) {
  register_gdal_drivers();
  const char* drv_name = format == ParcelFormat::GeoPackage ? "GPKG" : "GeoJSON";
  GDALDriver* drv = GetGDALDriverManager()->GetDriverByName(drv_name);
  if (!drv) throw std::runtime_error(std::string("GDAL driver missing: ") + drv_name);
  std::filesystem::remove(path);
  GdalDataset ds(drv->Create(path.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
  if (!ds) throw std::runtime_error(path + ": cannot create");
  OGRSpatialReference srs;
  srs.importFromEPSG(town.epsg);
  srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  OGRLayer* layer = ds->CreateLayer("parcels", &srs, wkbPolygon, nullptr);
  if (!layer) throw std::runtime_error(path + ": cannot create layer");
  OGRFieldDefn nib_f("NIB", OFTString), hak("TIPEHAK", OFTString), luas("LUASTERTUL", OFTReal),
      peta("LUASPETA", OFTReal);
  for (auto* f : {&nib_f, &hak, &luas, &peta}) layer->CreateField(f);
  ds->StartTransaction();
  for (const auto& p : town.parcels) {
    OGRFeature feat(layer->GetLayerDefn());
    feat.SetField("NIB", p.id.c_str());
    feat.SetField("TIPEHAK", p.right_type.c_str());
    feat.SetField("LUASTERTUL", p.official_area);
    feat.SetField("LUASPETA", std::round(area(p.shape)));
    OGRPolygon poly;
    OGRLinearRing ring;
    for (const auto& v : p.shape.front().outer) ring.addPoint(v.x(), v.y());
    ring.closeRings();
    poly.addRing(&ring);
    feat.SetGeometry(&poly);
    if (layer->CreateFeature(&feat) != OGRERR_NONE) throw std::runtime_error(path + ": write failed");
  }
  ds->CommitTransaction();
}

void write_dtm(const SampleTown& town, const std::string& path) {
  register_gdal_drivers();
  GDALDriver* drv = GetGDALDriverManager()->GetDriverByName("GTiff");
  const Dtm& d = town.dtm;
  const char* opts[] = {"COMPRESS=DEFLATE", "TILED=YES", nullptr};
  GdalDataset ds(
      drv->Create(path.c_str(), d.nx, d.ny, 1, GDT_Float32, const_cast<char**>(opts)));
  if (!ds) throw std::runtime_error(path + ": cannot create");
  double gt[6] = {d.x0 - 0.5, d.dx, 0, d.y0 + 0.5, 0, d.dy};
  ds->SetGeoTransform(gt);
  ds->SetProjection(town.crs_wkt.c_str());
  std::vector<float> z = d.z;
  const float nodata = -9999.f;
  for (size_t i = 0; i < z.size(); ++i)
    if (town.dtm_nodata[i]) z[i] = nodata;
  GDALRasterBand* band = ds->GetRasterBand(1);
  band->SetNoDataValue(nodata);
  if (band->RasterIO(GF_Write, 0, 0, d.nx, d.ny, z.data(), d.nx, d.ny, GDT_Float32, 0, 0) != CE_None)
    throw std::runtime_error(path + ": write failed");
}

}  // namespace

std::string truth_json(const SampleTown& town) {
  nlohmann::ordered_json j;
  j["generator"] = "cadastre3d sample";
  j["seed"] = town.seed;
  j["epsg"] = town.epsg;
  j["local_origin"] = {town.frame.origin.x(), town.frame.origin.y(), town.frame.origin.z()};
  j["conventions"] = {
      {"ground_level", "mean of the 1 m DTM cells whose centres lie in the footprint; walls start there"},
      {"wall", "exterior walls from the ground level to the roof plane at the wall line, gables and roof steps included"},
      {"party_wall", "full shared face, reported by each of the two attached houses"},
      {"outer_ceiling", "roof plan area minus footprint"},
      {"eave_height", "lowest roof vertex above ground level (overhang edge)"},
      {"wall_top_height", "lowest point where an exterior wall meets the roof"}};
  bool curved = false;
  for (const auto& p : town.truth)
    for (const auto& tb : p) curved = curved || tb.exact_areas;
  if (curved)
    j["conventions"]["curved_roof"] =
        "areas and volume of the exact surface (cylinder, sphere, cone, onion profile); the points lie on a "
        "tessellation within 2 mm of it; a roof bulging past its walls has no outer ceiling, its underside is roof";
  auto parcels = nlohmann::ordered_json::array();
  for (size_t i = 0; i < town.parcels.size(); ++i) {
    const Parcel& p = town.parcels[i];
    nlohmann::ordered_json pj;
    pj["parcel_id"] = p.id;
    pj["right_type"] = p.right_type;
    pj["layout"] = to_string(town.layouts[i]);
    pj["polygon_area_m2"] = r6(area(p.shape));
    pj["official_area_m2"] = p.official_area;
    auto bs = nlohmann::ordered_json::array();
    for (const auto& tb : town.truth[i]) bs.push_back(building_json(tb, town.frame));
    pj["buildings"] = bs;
    parcels.push_back(pj);
  }
  j["parcels"] = parcels;
  return j.dump(1);
}

SampleFiles write_sample_town(const SampleTown& town, const std::string& dir, ParcelFormat format,
                              const CloudLayout& cloud) {
  namespace fs = std::filesystem;
  fs::create_directories(dir);
  SampleFiles f;
  f.parcels = (fs::path(dir) / (format == ParcelFormat::GeoPackage ? "parcels.gpkg" : "parcels.geojson")).string();
  f.dtm = (fs::path(dir) / "dtm.tif").string();
  f.truth = (fs::path(dir) / "truth.json").string();
  write_parcels(town, f.parcels, format);
  write_dtm(town, f.dtm);
  if (!town.cloud.points.empty() && cloud.tile_size > 0) {
    f.cloud = (fs::path(dir) / "cloud").string();
    f.cloud_tiles = write_cloud_tiles(town.cloud, f.cloud, cloud);
  } else if (!town.cloud.points.empty()) {
    f.cloud = (fs::path(dir) / (cloud.laz ? "cloud.laz" : "cloud.las")).string();
    (cloud.laz ? write_laz : write_las)(f.cloud, town.cloud, 6, 4);
  }
  std::ofstream(f.truth) << truth_json(town) << "\n";
  return f;
}

}  // namespace c3d
