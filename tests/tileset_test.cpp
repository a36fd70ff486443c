// 3D Tiles of a batch (ifc_citygml/tileset.cpp), judged by others: the
// tileset read back and traversed by 3d-tiles-tools (npm, Cesium), every
// glTF by the Khronos gltf-validator, the property tables read by
// 3d-tiles-tools' metadata reader, and the placement by GDAL's transformation
// to Earth-centred coordinates (gdaltransform).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/geometry/geometry.h"
#include "ifc_citygml/export.h"
#include "tests/export_fixtures.h"
#include "tests/test_support.h"
#include "valuation/valuation_types.h"

namespace c3d {
namespace {

using nlohmann::json;

const std::string kJs = std::string(C3D_SOURCE_DIR) + "/tests/js";

// tiles_check.js's verdict on the tileset written from `m` (with `values`).
json written_and_checked(const BatchModel& m, const std::vector<ParcelValuation>& values, const std::string& name) {
  const std::string dir = test::temp_dir(name);
  auto w = tileset_writer(m, dir);
  w->values(values);
  w->add(m);
  w->finish();
  int rc = -1;
  const std::string out = test::shell("node " + kJs + "/tiles_check.js " + dir + " 2>&1", &rc);
  EXPECT_EQ(rc, 0) << out;
  return json::parse(out);
}

bool tools_present() {
  return std::filesystem::exists(kJs + "/node_modules/3d-tiles-tools/package.json") &&
         std::filesystem::exists(kJs + "/node_modules/gltf-validator/package.json") &&
         !test::shell("command -v node").empty();
}

// Property table `cls` of every leaf's content (parents: `leaves` false), as rows.
std::vector<json> rows_of(const json& check, const std::string& cls, bool leaves = true) {
  std::vector<json> rows;
  for (const json& c : check["contents"])
    if (c["leaf"] == leaves)
      for (const json& t : c["tables"])
      if (t["class"] == cls)
        for (const json& r : t["rows"]) rows.push_back(r);
  return rows;
}

TEST(Tileset, EveryBuildingOnceWithTheStoresAreasAndValue) {
  C3D_NEED(tools_present(), "tests/js/node_modules (3d-tiles-tools, gltf-validator; scripts/setup.sh) or node missing");
  const BatchModel m = fixture::sample_batch();
  ParcelValuation v;
  v.parcel_id = "P-001";
  v.currency = "IDR";
  v.building_value = 1.5e8, v.njop = 4.5e8, v.tax = 3.1e5, v.land_area = 112;
  CostItem roof;
  roof.building_id = "P-001_b1", roof.element_index = 0, roof.amount = 2.25e6;
  v.items.push_back(roof);
  const json check = written_and_checked(m, {v}, "tileset_values");
  EXPECT_EQ(check["version"], "1.1");
  EXPECT_EQ(check["glTFErrors"], 0);
  EXPECT_EQ(check["glTFWarnings"], 0);
  EXPECT_TRUE(check["regionsNested"]);
  std::map<std::string, json> by_id;
  for (const json& r : rows_of(check, "building")) by_id[r["building_id"]] = r;
  size_t elements = 0;
  for (const ParcelResult& r : m.results)
    for (const Building& b : r.buildings) {
      ASSERT_TRUE(by_id.count(b.id)) << b.id;
      const json& row = by_id[b.id];
      const BuildingTotals t = totals(b);
      EXPECT_NEAR(row["roof_area_m2"].get<double>(), t.roof, 1e-9);
      EXPECT_NEAR(row["wall_area_m2"].get<double>(), t.wall, 1e-9);
      EXPECT_NEAR(row["party_wall_area_m2"].get<double>(), t.party_wall, 1e-9);
      EXPECT_NEAR(row["outer_ceiling_area_m2"].get<double>(), t.outer_ceiling, 1e-9);
      EXPECT_NEAR(row["volume_m3"].get<double>(), b.volume, 1e-9);
      EXPECT_EQ(row["parcel_id"], r.parcel_id);
      EXPECT_EQ(row["lod"], to_string(b.lod));
      elements += b.elements.size();
    }
  EXPECT_EQ(by_id.size(), 4u);
  EXPECT_DOUBLE_EQ(by_id["P-001_b1"]["building_value"].get<double>(), 1.5e8);
  EXPECT_DOUBLE_EQ(by_id["P-001_b1"]["njop_per_m2"].get<double>(), 4.5e8 / 112);
  EXPECT_EQ(by_id["P-002_b1"]["currency"], "");  // not valued
  const std::vector<json> els = rows_of(check, "element");
  ASSERT_EQ(els.size(), elements);
  size_t priced = 0;
  for (const json& e : els)
    if (e["amount"].is_number() && e["amount"].get<double>() > 0) {
      ++priced;
      EXPECT_DOUBLE_EQ(e["amount"].get<double>(), 2.25e6);
    }
  EXPECT_EQ(priced, 1u);
  // The parents draw every building of so small a batch again, with the same figures.
  std::map<std::string, size_t> in_parents;
  for (const json& r : rows_of(check, "building", false)) {
    ++in_parents[r["building_id"]];
    EXPECT_EQ(r["roof_area_m2"], by_id[r["building_id"]]["roof_area_m2"]);
  }
  EXPECT_EQ(in_parents.size(), by_id.size());
}

// ECEF of world points (EPSG:32748 + height) by GDAL's command line.
std::vector<Vec3> ecef_by_gdal(const std::vector<Vec3>& world) {
  std::ostringstream in;
  in.precision(15);
  for (const Vec3& p : world) in << p.x() << " " << p.y() << " " << p.z() << "\\n";
  const std::string out =
      test::shell("printf '" + in.str() + "' | gdaltransform -s_srs EPSG:32748 -t_srs EPSG:4978");
  std::istringstream s(out);
  std::vector<Vec3> ecef;
  double x, y, z;
  while (s >> x >> y >> z) ecef.emplace_back(x, y, z);
  return ecef;
}

// Each content's transform, composed from the root, carries the least corner
// of its positions (the accessor's min, x, y and z each the least of any
// vertex) to where GDAL puts the least corner of its buildings' world
// coordinates: within 1 cm and the tangent frame's departure from the Earth,
// d² / 2R at the corner's distance d from the tile's centre (5 mm at 250 m).
TEST(Tileset, ContentsStandWhereGdalPutsThem) {
  C3D_NEED(tools_present(), "tests/js/node_modules (3d-tiles-tools, gltf-validator; scripts/setup.sh) or node missing");
  C3D_NEED(!test::shell("command -v gdaltransform").empty(), "gdaltransform (gdal-bin) missing");
  BatchModel m = fixture::grid_batch(120);  // 800 m x 60 m: four cells
  m.crs_wkt = "EPSG:32748";
  const json check = written_and_checked(m, {}, "tileset_place");
  ASSERT_GE(check["contents"].size(), 4u);
  std::map<std::string, const Building*> buildings;
  for (const ParcelResult& r : m.results)
    for (const Building& b : r.buildings) buildings[b.id] = &b;
  size_t seen = 0;
  for (const json& c : check["contents"]) {
    Vec3 lo = Vec3::Constant(INFINITY);
    for (const json& t : c["tables"])
      if (t["class"] == "building")
        for (const json& r : t["rows"]) {
          const Building& b = *buildings.at(r["building_id"].get<std::string>());
          seen += c["leaf"].get<bool>() ? 1 : 0;
          for (const Element& e : b.elements)
            for (const Face& f : e.faces)
              for (const Vec3& p : f.ring) lo = lo.cwiseMin(m.frame.to_world(p));
        }
    const std::vector<double> t = c["transform"].get<std::vector<double>>();
    const std::vector<double> q = c["positionMin"].get<std::vector<double>>();
    Vec3 placed;
    for (int k = 0; k < 3; ++k) placed[k] = t[size_t(k)] * q[0] + t[size_t(4 + k)] * q[1] + t[size_t(8 + k)] * q[2] + t[size_t(12 + k)];
    const std::vector<Vec3> truth = ecef_by_gdal({lo});
    ASSERT_EQ(truth.size(), 1u);
    const double d = Vec3(q[0], q[1], 0).norm();
    EXPECT_LT((placed - truth[0]).norm(), 0.01 + d * d / (2 * 6.371e6)) << c["uri"];
    if (c["leaf"]) EXPECT_LT((placed - truth[0]).norm(), 0.01) << c["uri"];
  }
  EXPECT_EQ(seen, m.results.size());  // each in one leaf
}

// tileset_view.js on the tileset in dir with options (its flags): the page
// ready, no console error, roofs and walls drawn in their colours. Its JSON.
json drawn(const std::string& dir, const std::string& options) {
  int rc = -1;
  const std::string out =
      test::shell("node " + kJs + "/tileset_view.js " + dir + " " + dir + "/view.png " + options + " 2>&1", &rc);
  EXPECT_EQ(rc, 0) << out;
  json v = json::parse(out, nullptr, false);
  if (v.is_discarded()) {
    ADD_FAILURE() << out;
    return json::object();
  }
  EXPECT_EQ(v["state"], "ready");
  EXPECT_TRUE(v["errors"].empty()) << v["errors"];
  EXPECT_GT(v["pixels"]["roof"].get<int>(), 1000) << out;
  EXPECT_GT(v["pixels"]["wall"].get<int>(), 200) << out;
  return v;
}

// CesiumJS in headless Chromium draws the tileset: roofs and walls in their
// colours (the attached houses' party wall stands between them, unseen), no
// console error.
TEST(Tileset, CesiumDrawsTheElementsInTheirColours) {
  C3D_NEED(tools_present() && std::filesystem::exists(kJs + "/node_modules/cesium/package.json") &&
               std::filesystem::exists(kJs + "/node_modules/puppeteer-core/package.json") &&
               !test::shell("command -v chromium").empty(),
           "tests/js/node_modules (cesium, puppeteer-core; scripts/setup.sh) or chromium missing");
  const std::string dir = test::temp_dir("tileset_view");
  auto w = tileset_writer(fixture::sample_batch(), dir);
  w->add(fixture::sample_batch());
  w->finish();
  drawn(dir, "");
}

// The page the writer puts beside the tileset (view.html: three.js and
// 3d-tiles-renderer) in headless Chromium: it draws the elements in their
// colours, and a click on a roof marks it and names its parcel and area as
// the model holds them.
TEST(Tileset, ItsOwnPageDrawsAndNamesAClickedRoof) {
  C3D_NEED(tools_present() && std::filesystem::exists(kJs + "/node_modules/puppeteer-core/package.json") &&
               !test::shell("command -v chromium").empty(),
           "tests/js/node_modules (puppeteer-core; scripts/setup.sh) or chromium missing");
  const std::string dir = test::temp_dir("tileset_own_view");
  const BatchModel m = fixture::sample_batch();
  auto w = tileset_writer(m, dir);
  w->add(m);
  const std::vector<std::string> written = w->finish();
  EXPECT_EQ(written.size(), 3u);  // tileset.json, view.html, lib/c3d-tiles.js
  const json v = drawn(dir, "--own --click");
  ASSERT_TRUE(v["picked"].is_object()) << v;
  const std::string parcel = v["picked"]["parcel"];
  const double area = std::stod(v["picked"]["area"].get<std::string>());
  std::vector<double> roofs;  // the parcel's roof areas in the model
  for (const ParcelResult& r : m.results)
    if (r.parcel_id == parcel)
      for (const Building& b : r.buildings)
        for (const Element& e : b.elements)
          if (e.type == ElementType::Roof) roofs.push_back(e.area);
  ASSERT_FALSE(roofs.empty()) << "no parcel " << parcel;
  EXPECT_TRUE(std::any_of(roofs.begin(), roofs.end(), [&](double a) { return std::abs(a - area) < 1e-9 * a; }))
      << area << " m2 is none of parcel " << parcel << "'s roofs";
  char shown[32];  // as printed, 2 decimals (the sample's roofs are under 1,000 m2: no thousands comma)
  std::snprintf(shown, sizeof shown, "Area %.2f", area);
  EXPECT_NE(v["picked"]["text"].get<std::string>().find(shown), std::string::npos) << v;
  EXPECT_GT(v["picked"]["marked"].get<int>(), 500) << "the picked roof is not marked: " << v;
  // The sample is not valued: its -1s read as no value, not as 0.
  EXPECT_NE(v["picked"]["text"].get<std::string>().find("Building value \u2014"), std::string::npos) << v;
  // Opened from the file, where a browser fetches nothing, it says how to serve it.
  int from_file = -1;
  const std::string note =
      test::shell("node " + kJs + "/tileset_view.js " + dir + " " + dir + "/file.png --own --from-file 2>&1", &from_file);
  EXPECT_EQ(from_file, 0) << note;
  EXPECT_NE(note.find("\"state\":\"unavailable\""), std::string::npos) << note;
  EXPECT_NE(note.find("serve this folder over HTTP"), std::string::npos) << note;
}

TEST(Tileset, ABatchWithoutACrsSaysSo) {
  BatchModel m = fixture::sample_batch();
  m.crs_wkt.clear();
  try {
    tileset_writer(m, test::temp_dir("tileset_no_crs"));
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("CRS"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace c3d
