// The store's GIS layers (issue 36): a 2D building_footprint, roof_part and
// parcel layer that GDAL/QGIS open with their geometry type, SRS, extent and
// R-tree index, every geometry valid by GEOS, every figure on the row (no
// join), LADM code-list values, a default QGIS style by value; and a store
// written before these layers still opens, resumes, reports and exports.
#include <gdal.h>
#include <gtest/gtest.h>
#include <ogrsf_frmts.h>
#include <sqlite3.h>

#include <filesystem>
#include <memory>

#include "cadastre/store/gis.h"
#include "cadastre/store/store.h"
#include "core/config/config.h"
#include "core/geometry/geometry.h"
#include "tests/store_fixtures.h"
#include "tests/test_support.h"
#include "valuation/valuation.h"

using namespace c3d;
namespace fs = std::filesystem;

namespace {

ParcelAttribute attribute(const std::string& name, ParcelAttribute::Kind kind, const std::string& value) {
  return {name, kind, value.empty(), value};
}

// The sample batch, the first parcel with fields of its own (one named like a column of ours).
BatchModel batch_with_fields() {
  BatchModel m = test::sample_batch();
  using K = ParcelAttribute::Kind;
  m.parcels[0].attributes = {attribute("KECAMATAN", K::Text, "Cimahi Selatan"), attribute("NIB", K::Integer, "42"),
                             attribute("LUASTERTUL", K::Real, "250.5"), attribute("njop", K::Real, "1.5"),
                             attribute("CATATAN", K::Text, "")};
  return m;
}

std::string make_store(const std::string& name, const BatchModel& m) {
  std::string path = test::temp_dir(name) + "/cadastre.gpkg";
  Store s;
  s.open(path, "", m.epsg);
  s.begin_run("{}", {}, m.frame);
  Config c = default_config();
  for (size_t i = 0; i < m.parcels.size(); ++i)
    s.write_parcel(m.parcels[i], m.results[i], value_parcel(m.parcels[i], m.results[i], c.valuation), m.frame,
                   "k");
  s.end_run();
  return path;
}

using Dataset = std::unique_ptr<GDALDataset, void (*)(GDALDataset*)>;
Dataset open_ogr(const std::string& path) {
  GDALAllRegister();
  return Dataset(GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY),
                 [](GDALDataset* d) { GDALClose(d); });
}

std::string one(const std::string& path, const std::string& sql) {
  sqlite3* db = nullptr;
  sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr);
  sqlite3_stmt* s = nullptr;
  std::string out = "<error>";
  if (sqlite3_prepare_v2(db, sql.c_str(), -1, &s, nullptr) == SQLITE_OK) {
    out = sqlite3_step(s) == SQLITE_ROW && sqlite3_column_text(s, 0)
              ? reinterpret_cast<const char*>(sqlite3_column_text(s, 0))
              : "NULL";
  }
  sqlite3_finalize(s);
  sqlite3_close(db);
  return out;
}

}  // namespace

TEST(GpkgLayers, BuildingFootprintIsOneValid2DPolygonWithEveryFigure) {
  const BatchModel m = batch_with_fields();
  const std::string path = make_store("footprint", m);
  auto ds = open_ogr(path);
  ASSERT_TRUE(ds);
  OGRLayer* l = ds->GetLayerByName("building_footprint");
  ASSERT_NE(l, nullptr) << "no building_footprint layer";
  EXPECT_EQ(l->GetGeomType(), wkbMultiPolygon);  // 2D: a GIS area is the footprint's
  ASSERT_NE(l->GetSpatialRef(), nullptr);
  EXPECT_STREQ(l->GetSpatialRef()->GetAuthorityCode(nullptr), "32748");
  ASSERT_EQ(l->GetFeatureCount(), 1);
  std::unique_ptr<OGRFeature> f(l->GetNextFeature());
  const auto* g = f->GetGeometryRef()->toMultiPolygon();
  EXPECT_TRUE(g->IsValid());
  EXPECT_NEAR(g->get_Area(), 80.0, 1e-6);  // the 10 x 8 m ground, once
  const Building& b = m.results[0].buildings[0];
  const BuildingTotals t = totals(b);
  EXPECT_STREQ(f->GetFieldAsString("parcel_id"), "32.73.01");
  EXPECT_STREQ(f->GetFieldAsString("building_id"), b.id.c_str());
  EXPECT_NEAR(f->GetFieldAsDouble("ground_area"), 80.0, 1e-6);
  EXPECT_NEAR(f->GetFieldAsDouble("roof_area"), t.roof, 1e-6);
  EXPECT_NEAR(f->GetFieldAsDouble("sigma_roof_area"), t.sigma_roof, 1e-6);
  EXPECT_NEAR(f->GetFieldAsDouble("wall_area"), t.wall, 1e-6);
  EXPECT_NEAR(f->GetFieldAsDouble("volume"), b.volume, 1e-6);
  EXPECT_NEAR(f->GetFieldAsDouble("ridge_height"), 5.0, 1e-9);
  EXPECT_NEAR(f->GetFieldAsDouble("ground_z"), m.frame.origin.z() + 1.5, 1e-9);  // world height
  EXPECT_STREQ(f->GetFieldAsString("lod"), "2.2");
  EXPECT_GE(f->GetFieldIndex("roof_type"), 0);
  EXPECT_GE(f->GetFieldIndex("roof_z_70p"), 0);
  const ParcelValuation v = value_parcel(m.parcels[0], m.results[0], default_config().valuation);
  EXPECT_GT(v.njop, 0);
  EXPECT_NEAR(f->GetFieldAsDouble("parcel_njop"), v.njop, 1e-6 * v.njop);
  EXPECT_NEAR(f->GetFieldAsDouble("parcel_tax"), v.tax, 1e-6 * (1 + v.tax));
  EXPECT_GT(f->GetFieldAsDouble("building_cost"), 0);
}

TEST(GpkgLayers, RoofPartsAreValidPlansWithTheirElementFigures) {
  const BatchModel m = test::sample_batch();
  const std::string path = make_store("roof_part", m);
  auto ds = open_ogr(path);
  ASSERT_TRUE(ds);
  OGRLayer* l = ds->GetLayerByName("roof_part");
  ASSERT_NE(l, nullptr) << "no roof_part layer";
  EXPECT_EQ(l->GetGeomType(), wkbMultiPolygon);
  ASSERT_EQ(l->GetFeatureCount(), 2);
  const Building& b = m.results[0].buildings[0];
  for (auto& f : *l) {
    const auto* g = f->GetGeometryRef();
    EXPECT_TRUE(g->IsValid());
    EXPECT_NEAR(g->toMultiPolygon()->get_Area(), 10 * 4.5, 1e-6);  // plan of one gable half
    const Element& e = b.elements[size_t(f->GetFieldAsInteger("element_index"))];
    EXPECT_NEAR(f->GetFieldAsDouble("area"), e.area, 1e-9);  // the 3D area stays the attribute
    EXPECT_NEAR(f->GetFieldAsDouble("slope_deg"), e.slope_deg, 1e-9);
    EXPECT_NEAR(f->GetFieldAsDouble("azimuth_deg"), e.azimuth_deg, 1e-9);
    EXPECT_NEAR(f->GetFieldAsDouble("sigma_area"), e.sigma_area, 1e-9);
    EXPECT_STREQ(f->GetFieldAsString("parcel_id"), "32.73.01");
  }
}

TEST(GpkgLayers, SelfIntersectingPlanIsRepairedAndKeepsItsArea) {
  // A roof face whose plan is a bow tie: two 1 x 1 triangles crossing at (1, 0.5).
  Face f;
  f.ring = {{0, 0, 3}, {2, 1, 3.2}, {2, 0, 3.1}, {0, 1, 3.1}};
  bool repaired = false;
  const MultiPolygon2 plan = store_gis::plan_of({f}, Vec3(781000, 9240000, 0), &repaired);
  EXPECT_TRUE(repaired);
  EXPECT_EQ(plan.size(), 2u);
  EXPECT_NEAR(area(plan), 1.0, 1e-9);
  // Faces of one element that share an edge become one polygon (a MultiPolygon
  // of two touching squares is invalid in 2D).
  Face a, b;
  a.ring = {{0, 0, 3}, {1, 0, 3}, {1, 1, 3}, {0, 1, 3}};
  b.ring = {{1, 0, 3}, {2, 0, 3}, {2, 1, 3}, {1, 1, 3}};
  const MultiPolygon2 two = store_gis::plan_of({a, b}, Vec3::Zero(), &repaired);
  EXPECT_FALSE(repaired);
  EXPECT_EQ(two.size(), 1u);
  EXPECT_NEAR(area(two), 2.0, 1e-9);
}

TEST(GpkgLayers, ParcelLayerCarriesValuationAndTheInputLayersFields) {
  const BatchModel m = batch_with_fields();
  const std::string path = make_store("parcel", m);
  auto ds = open_ogr(path);
  ASSERT_TRUE(ds);
  OGRLayer* l = ds->GetLayerByName("parcel");
  ASSERT_NE(l, nullptr) << "no parcel layer";
  EXPECT_EQ(l->GetGeomType(), wkbMultiPolygon);
  ASSERT_EQ(l->GetFeatureCount(), 3);
  const OGRFeatureDefn* d = l->GetLayerDefn();
  ASSERT_GE(d->GetFieldIndex("KECAMATAN"), 0);
  EXPECT_EQ(d->GetFieldDefn(d->GetFieldIndex("NIB"))->GetType(), OFTInteger64);
  EXPECT_EQ(d->GetFieldDefn(d->GetFieldIndex("LUASTERTUL"))->GetType(), OFTReal);
  ASSERT_GE(d->GetFieldIndex("src_njop"), 0);  // the input's own "njop" beside ours
  const Config c = default_config();
  for (auto& f : *l) {
    EXPECT_TRUE(f->GetGeometryRef()->IsValid());
    const int i = f->GetFieldAsInteger("layer_index");
    const ParcelValuation v = value_parcel(m.parcels[size_t(i)], m.results[size_t(i)], c.valuation);
    EXPECT_NEAR(f->GetFieldAsDouble("njop"), v.njop, 1e-6 * (1 + v.njop)) << i;
    EXPECT_NEAR(f->GetFieldAsDouble("tax"), v.tax, 1e-6 * (1 + v.tax)) << i;
    EXPECT_STREQ(f->GetFieldAsString("status"), to_string(m.results[size_t(i)].status));
    if (i != 0) continue;
    EXPECT_STREQ(f->GetFieldAsString("KECAMATAN"), "Cimahi Selatan");
    EXPECT_EQ(f->GetFieldAsInteger64("NIB"), 42);
    EXPECT_DOUBLE_EQ(f->GetFieldAsDouble("LUASTERTUL"), 250.5);
    EXPECT_DOUBLE_EQ(f->GetFieldAsDouble("src_njop"), 1.5);
    EXPECT_FALSE(f->IsFieldSetAndNotNull(d->GetFieldIndex("CATATAN")));
    EXPECT_EQ(f->GetFieldAsInteger("buildings"), 1);
    EXPECT_NEAR(f->GetFieldAsDouble("ground_area"), 80.0, 1e-6);
  }
}

TEST(GpkgLayers, EveryGeometryTableHasAnRTreeIndexAndAnExtent) {
  BatchModel m = test::sample_batch();
  const std::string path = make_store("rtree", m);
  for (const char* t : {"parcel", "building_footprint", "roof_part", "la_spatialunit", "building", "building_element"}) {
    const std::string table = t;
    EXPECT_EQ(one(path, "SELECT scope FROM gpkg_extensions WHERE extension_name='gpkg_rtree_index' AND table_name='" +
                            table + "'"),
              "write-only")
        << t;
    EXPECT_EQ(one(path, "SELECT count(*) FROM rtree_" + table + "_geom"),
              one(path, "SELECT count(*) FROM " + table + " WHERE geom IS NOT NULL"))
        << t;
    EXPECT_NE(one(path, "SELECT min_x FROM gpkg_contents WHERE table_name='" + table + "'"), "NULL") << t;
  }
  // The triggers keep the index: rewriting a parcel leaves one entry per row.
  {
    Store s;
    s.open(path, "", m.epsg);
    s.write_parcel(m.parcels[0], m.results[0], value_parcel(m.parcels[0], m.results[0], default_config().valuation),
                   m.frame, "k");
    s.end_run();
  }
  EXPECT_EQ(one(path, "SELECT count(*) FROM rtree_roof_part_geom"), "2");
  EXPECT_EQ(one(path, "SELECT count(*) FROM rtree_roof_part_geom r JOIN roof_part p ON p.fid = r.id"), "2");
  auto ds = open_ogr(path);
  ASSERT_TRUE(ds);
  OGRLayer* l = ds->GetLayerByName("building_footprint");
  ASSERT_NE(l, nullptr);
  EXPECT_TRUE(l->TestCapability(OLCFastSpatialFilter));  // GDAL sees the index
  OGREnvelope env;
  ASSERT_EQ(l->GetExtent(&env, FALSE), OGRERR_NONE);
  EXPECT_NEAR(env.MinX, m.frame.origin.x() + 3, 1e-6);
  l->SetSpatialFilterRect(env.MinX - 1, env.MinY - 1, env.MaxX + 1, env.MaxY + 1);
  EXPECT_EQ(l->GetFeatureCount(), 1);
}

TEST(GpkgLayers, LadmCodeListValues) {
  const std::string path = make_store("ladm", test::sample_batch());
  // ISO 19152 LA_PartyType has no 'unknown': a right whose holder the parcel layer
  // does not name has no party (LA_RRR - LA_Party is 0..1).
  EXPECT_EQ(one(path, "SELECT count(*) FROM la_party WHERE party_type NOT IN "
                      "('naturalPerson','nonNaturalPerson','baunit','group')"),
            "0");
  EXPECT_EQ(one(path, "SELECT count(*) FROM la_rrr WHERE party_id IS NOT NULL"), "0");
  EXPECT_EQ(one(path, "SELECT rrr_type FROM la_rrr r JOIN la_baunit b ON b.fid=r.baunit_id WHERE parcel_id='32.73.01'"),
            "ownership");  // Hak Milik
  EXPECT_EQ(one(path, "SELECT rrr_type FROM la_rrr r JOIN la_baunit b ON b.fid=r.baunit_id WHERE parcel_id='32.73.02'"),
            "superficies");  // Hak Guna Bangunan
  EXPECT_EQ(one(path, "SELECT local_type FROM la_rrr r JOIN la_baunit b ON b.fid=r.baunit_id "
                      "WHERE parcel_id='32.73.02'"),
            "Hak Guna Bangunan");
  EXPECT_EQ(one(path, "SELECT DISTINCT baunit_type FROM la_baunit"), "basicPropertyUnit");
  EXPECT_EQ(load_batch_model(path).parcels[1].right_type, "Hak Guna Bangunan");  // the report's name
}

TEST(GpkgLayers, QgisDefaultStyleColoursParcelsByValue) {
  const std::string path = make_store("style", test::sample_batch(3));
  EXPECT_EQ(one(path, "SELECT data_type FROM gpkg_contents WHERE table_name='layer_styles'"), "attributes");
  const std::string qml =
      one(path, "SELECT styleQML FROM layer_styles WHERE f_table_name='parcel' AND f_geometry_column='geom' "
                "AND useAsDefault=1");
  EXPECT_NE(qml.find("type=\"graduatedSymbol\" attr=\"njop\""), std::string::npos) << qml;
  EXPECT_NE(qml.find("<range lower="), std::string::npos) << qml;
  EXPECT_NE(one(path, "SELECT count(*) FROM layer_styles WHERE f_table_name='building_footprint'"), "0");
}

TEST(GpkgLayers, StoreWrittenBeforeStillOpensResumesAndExports) {
  // tests/data/store_before_gis.gpkg: 3 parcels of a sample town written by
  // cadastre3d at fd8c68a (no GIS layers, 'unknown' parties, local right names).
  const std::string dir = test::temp_dir("old");
  const std::string path = dir + "/cadastre.gpkg";
  fs::copy_file(std::string(C3D_SOURCE_DIR) + "/tests/data/store_before_gis.gpkg", path);
  const BatchModel before = load_batch_model(path);  // read as it is
  ASSERT_EQ(before.parcels.size(), 3u);
  EXPECT_EQ(before.parcels[0].right_type.rfind("Hak ", 0), 0u) << before.parcels[0].right_type;
  {
    Store s;  // opening for a resume migrates it
    s.open(path, before.crs_wkt, before.epsg);
    s.begin_run("{}", {}, before.frame);
    s.write_parcel(before.parcels[0], before.results[0],
                   value_parcel(before.parcels[0], before.results[0], default_config().valuation), before.frame, "k");
    s.end_run();
  }
  const BatchModel after = load_batch_model(path);
  ASSERT_EQ(after.parcels.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(after.parcels[i].right_type, before.parcels[i].right_type) << i;
    ASSERT_EQ(after.results[i].buildings.size(), before.results[i].buildings.size()) << i;
    for (size_t k = 0; k < after.results[i].buildings.size(); ++k)
      EXPECT_NEAR(totals(after.results[i].buildings[k]).roof, totals(before.results[i].buildings[k]).roof, 1e-6);
  }
  EXPECT_EQ(one(path, "SELECT count(*) FROM la_party WHERE party_type='unknown'"), "0");
  EXPECT_EQ(one(path, "SELECT count(*) FROM la_rrr WHERE rrr_type NOT IN ('ownership','superficies')"), "0");
  size_t buildings = 0;
  for (const ParcelResult& r : after.results) buildings += r.buildings.size();
  // Every parcel in the GIS layers: the rewritten one and those filled in from their 3D rows.
  EXPECT_EQ(one(path, "SELECT count(*) FROM building_footprint"), std::to_string(buildings));
  EXPECT_EQ(one(path, "SELECT count(*) FROM parcel"), "3");
  EXPECT_EQ(one(path, "SELECT count(*) FROM rtree_building_geom"), one(path, "SELECT count(*) FROM building"));
  std::string log;
  EXPECT_EQ(test::run_cli("export --store " + path + " --out " + dir + "/exp --formats cityjson", &log), 0) << log;
}
