// CityJSON 2.0 export: schema-valid (ajv with the 2.0.2 schema), every vertex index in
// range (checked here, the schema cannot), areas per semantic surface read back from
// the geometry, and the read-back model validates. Each surface once at the primary
// LoD (summed by type they give the element totals), lower LoDs as Solids beside
// it, the 3DBAG-style attributes, and CityJSONSeq.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "core/error.h"
#include "core/geometry/geometry.h"
#include "ifc_citygml/export.h"
#include "ifc_citygml/validate.h"
#include "tests/export_checks.h"
#include "tests/export_fixtures.h"
#include "tests/test_support.h"

using namespace c3d;
using nlohmann::json;
namespace fx = c3d::fixture;
using namespace c3d::check;

namespace {

// Faces of a closed shell typed as a LodShell's: by their normal.
LodShell lod_shell(Lod lod, std::vector<Face> faces, double rmse) {
  LodShell l;
  l.lod = lod;
  for (const auto& f : faces) {
    const double nz = unit_normal(f).z();
    l.face_types.push_back(nz < -0.9 ? ElementType::Ground : nz > 0.9 ? ElementType::Roof : ElementType::Wall);
  }
  l.faces = std::move(faces);
  l.roof_rmse = rmse;
  return l;
}

// The sample batch with what the reconstruction will add: the gable house's
// LoD 1.2 prism and LoD 1.3 block (filled by hand here) and its 3DBAG-style
// attributes; the other buildings keep theirs unset (NaN).
BatchModel with_lods_and_attributes() {
  BatchModel m = fx::sample_batch();
  Building& g = m.results[0].buildings[0];
  g.lower_lods = {lod_shell(Lod::Lod12, test::box_shell({0, 0, 0}, {10, 8, 4.5}), 0.9),
                  lod_shell(Lod::Lod13, test::box_shell({0, 0, 0}, {10, 8, 5.25}), 0.6)};
  g.attributes.roof_type = "slanted";
  g.attributes.roof_z_min = 2.7, g.attributes.roof_z_50p = 4.5;
  g.attributes.roof_z_70p = 5.1, g.attributes.roof_z_max = 6.0;
  g.attributes.roof_points = 812;
  g.attributes.point_density = 7.9;
  g.attributes.data_quality = "good";
  g.roof_deviation.n = 812, g.roof_deviation.rmse = 0.04;
  return m;
}

class CityJson : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = test::temp_dir("export_cityjson");
    path = dir + "/buildings.city.json";
    write_cityjson(model, path);
    doc = json::parse(fx::read_text(path));
  }
  BatchModel model = with_lods_and_attributes();
  std::string dir, path;
  json doc;
};

}  // namespace

TEST_F(CityJson, SchemaValid) {
  C3D_NEED(can_ajv(), "tests/js/node_modules (npm) or ../shared/schemas missing");
  std::string out;
  EXPECT_EQ(ajv(path, &out), 0) << out;
}

TEST_F(CityJson, BrokenFileFailsSchema) {
  C3D_NEED(can_ajv(), "tests/js/node_modules (npm) or ../shared/schemas missing");
  json bad = doc;
  bad["CityObjects"]["P-001_b1"]["geometry"][0]["lod"] = 2;  // must be a string
  fx::write_text(dir + "/bad.city.json", bad.dump());
  std::string out;
  EXPECT_NE(ajv(dir + "/bad.city.json", &out), 0) << out;
}

TEST_F(CityJson, HeaderAndIndices) {
  EXPECT_EQ(doc["version"], "2.0");
  EXPECT_EQ(doc["metadata"]["referenceSystem"], "https://www.opengis.net/def/crs/EPSG/0/32748");
  EXPECT_DOUBLE_EQ(doc["transform"]["scale"][0].get<double>(), 0.0001);
  EXPECT_DOUBLE_EQ(doc["transform"]["translate"][1].get<double>(), 9237654.0);
  EXPECT_EQ(bad_indices(doc), 0u);
  // Two roof levels: no BuildingParts (they would repeat the solid's
  // surfaces), each element's surface says its level.
  EXPECT_FALSE(doc["CityObjects"]["P-004_b1"].contains("children"));
  std::set<int> levels;
  for (const auto& s : doc["CityObjects"]["P-004_b1"]["geometry"][0]["semantics"]["surfaces"])
    levels.insert(s.at("roof_level").get<int>());
  EXPECT_EQ(levels, (std::set<int>{0, 1}));
  EXPECT_EQ(doc["CityObjects"]["P-001_b1"]["attributes"]["right_type"], "Hak Milik");
  // Negative: an index past the end is caught here and by the reader.
  json bad = doc;
  bad["CityObjects"]["P-001_b1"]["geometry"][0]["boundaries"][0][0][0] = doc["vertices"].size();
  EXPECT_EQ(bad_indices(bad), 1u);
  fx::write_text(dir + "/bad_index.city.json", bad.dump());
  EXPECT_THROW(read_cityjson(dir + "/bad_index.city.json"), InputError);
}

TEST_F(CityJson, PartyWallFlaggedOnSemanticSurface) {
  bool found = false;
  for (const auto& s : doc["CityObjects"]["P-002_b1"]["geometry"][0]["semantics"]["surfaces"])
    found = found || (s["type"] == "WallSurface" && s["is_party_wall"] == true);
  EXPECT_TRUE(found);
}

TEST_F(CityJson, AreasFromGeometryPerSemanticSurface) {
  BatchModel back = read_cityjson(path);
  ASSERT_EQ(back.results.size(), model.results.size());
  EXPECT_EQ(back.epsg, 32748);
  for (size_t r = 0; r < model.results.size(); ++r) {
    ASSERT_EQ(back.results[r].buildings.size(), 1u);
    const Building& a = model.results[r].buildings[0];
    const Building& b = back.results[r].buildings[0];
    ASSERT_EQ(a.elements.size(), b.elements.size()) << a.id;
    ASSERT_EQ(a.solid.size(), b.solid.size()) << a.id;
    for (size_t e = 0; e < a.elements.size(); ++e) {
      EXPECT_EQ(a.elements[e].type, b.elements[e].type) << a.id << " " << e;
      double geom = 0;
      for (const auto& f : b.elements[e].faces) geom += area(f);
      EXPECT_NEAR(geom, a.elements[e].area, 0.01) << a.id << " element " << e;
      EXPECT_NEAR(b.elements[e].area, a.elements[e].area, 0.01);
    }
  }
  auto issues = validate_model(back);
  EXPECT_TRUE(issues.empty()) << (issues.empty() ? "" : to_string(issues[0]));
}

TEST_F(CityJson, EachSurfaceOnceSummedByTypeGivesTheElementTotals) {
  // The primary LoD is the solid (its roof clipped inside the walls) and the
  // element parts outside it (overhangs, the outer ceiling): each surface once.
  // Before, the elements and the solid were both "lod 2": every area twice.
  const auto file = cityjson_type_areas(doc), store = store_type_areas(model);
  for (const auto& [type, a] : store) EXPECT_NEAR(file.count(type) ? file.at(type) : 0.0, a, 0.01) << type;
  EXPECT_EQ(file.size(), store.size());
  const json& gable = doc["CityObjects"]["P-001_b1"]["geometry"];
  EXPECT_EQ(gable[0]["type"], "Solid");
  EXPECT_EQ(gable[0]["lod"], "2.2");
  EXPECT_EQ(gable[1]["type"], "MultiSurface");  // overhangs and the outer ceiling
  EXPECT_EQ(gable[1]["lod"], "2.2");
  // The element's figures once: on its first surface object (the solid's).
  size_t described = 0;
  for (const auto& g : {gable[0], gable[1]})
    for (const auto& s : g["semantics"]["surfaces"])
      described += s.value("element_index", -1) == 0 && s.contains("area");
  EXPECT_EQ(described, 1u);
}

TEST_F(CityJson, LowerLodsAreSolidsBesideThePrimary) {
  std::vector<std::string> lods;
  for (const auto& g : doc["CityObjects"]["P-001_b1"]["geometry"]) {
    lods.push_back(g["lod"]);
    if (g["lod"] == "2.2") continue;
    EXPECT_EQ(g["type"], "Solid");
    std::set<std::string> types;
    for (const auto& s : g["semantics"]["surfaces"]) types.insert(s["type"]);
    EXPECT_EQ(types, (std::set<std::string>{"GroundSurface", "RoofSurface", "WallSurface"}));
    EXPECT_EQ(g["semantics"]["values"][0].size(), 6u);
  }
  EXPECT_EQ(lods, (std::vector<std::string>{"2.2", "2.2", "1.2", "1.3"}));
  const BatchModel back = read_cityjson(path);
  const Building& b = back.results[0].buildings[0];
  EXPECT_EQ(b.lod, Lod::Lod22);
  ASSERT_EQ(b.lower_lods.size(), 2u);
  EXPECT_EQ(b.lower_lods[0].lod, Lod::Lod12);
  EXPECT_EQ(b.lower_lods[1].faces.size(), 6u);
  EXPECT_EQ(b.lower_lods[1].face_types[0], model.results[0].buildings[0].lower_lods[1].face_types[0]);
  EXPECT_TRUE(validate_model(back).empty());
  // A broken lower LoD is the reader's and the validator's concern too.
  BatchModel broken = model;
  broken.results[0].buildings[0].lower_lods[0].faces.pop_back();
  write_cityjson(broken, dir + "/open_lod12.city.json");
  const auto issues = validate_model(read_cityjson(dir + "/open_lod12.city.json"));
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].code, kShellNotClosed);
  EXPECT_EQ(issues[0].where, "lod 1.2 solid");
}

TEST_F(CityJson, BuildingAttributesAfter3dbag) {
  const json& a = doc["CityObjects"]["P-001_b1"]["attributes"];
  EXPECT_EQ(a["roof_type"], "slanted");
  EXPECT_NEAR(a["roof_height_min"].get<double>(), 702.7, 1e-9);  // world z: local + origin 700
  EXPECT_NEAR(a["roof_height_50p"].get<double>(), 704.5, 1e-9);
  EXPECT_NEAR(a["roof_height_70p"].get<double>(), 705.1, 1e-9);
  EXPECT_NEAR(a["roof_height_max"].get<double>(), 706.0, 1e-9);
  EXPECT_NEAR(a["ground_height"].get<double>(), 700.0, 1e-9);
  EXPECT_DOUBLE_EQ(a["rmse_lod22"].get<double>(), 0.04);
  EXPECT_DOUBLE_EQ(a["rmse_lod12"].get<double>(), 0.9);
  EXPECT_DOUBLE_EQ(a["rmse_lod13"].get<double>(), 0.6);
  EXPECT_EQ(a["roof_points"], 812);
  EXPECT_DOUBLE_EQ(a["point_density"].get<double>(), 7.9);
  EXPECT_EQ(a["data_quality"], "good");
  EXPECT_DOUBLE_EQ(a["roof_area"].get<double>(), totals(model.results[0].buildings[0]).roof);
  // Unknown figures are left out, never null or NaN.
  const json& none = doc["CityObjects"]["P-003_b1"]["attributes"];
  for (const char* k : {"roof_height_min", "roof_height_max", "rmse_lod22", "point_density", "roof_type"})
    EXPECT_FALSE(none.contains(k)) << k;
  EXPECT_NEAR(none["ground_height"].get<double>(), 700.5, 1e-9);
  // Read back as they were (heights to local z).
  const Building& b = read_cityjson(path).results[0].buildings[0];
  EXPECT_EQ(b.attributes.roof_type, "slanted");
  EXPECT_NEAR(b.attributes.roof_z_70p, 5.1, 1e-9);
  EXPECT_TRUE(std::isnan(read_cityjson(path).results[2].buildings[0].attributes.roof_z_min));
}

TEST_F(CityJson, SeqIsAHeaderThenOneFeaturePerBuilding) {
  const auto& names = export_format_names();
  ASSERT_NE(std::find(names.begin(), names.end(), "cityjsonseq"), names.end());
  const auto written = export_formats(model, dir + "/seq", {"cityjsonseq"});
  ASSERT_EQ(written.size(), 1u);
  EXPECT_EQ(written[0], dir + "/seq/buildings.city.jsonl");
  std::istringstream in(fx::read_text(written[0]));
  std::vector<json> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(json::parse(line));
  ASSERT_EQ(lines.size(), 5u);  // header + 4 buildings
  EXPECT_EQ(lines[0]["type"], "CityJSON");
  EXPECT_EQ(lines[0]["transform"], doc["transform"]);
  EXPECT_EQ(lines[0]["metadata"], doc["metadata"]);
  EXPECT_TRUE(lines[0]["CityObjects"].empty());
  EXPECT_TRUE(lines[0]["vertices"].empty());
  std::map<std::string, double> sum;
  for (size_t k = 1; k < lines.size(); ++k) {
    const json& f = lines[k];
    EXPECT_EQ(f["type"], "CityJSONFeature");
    ASSERT_EQ(f["CityObjects"].size(), 1u);
    EXPECT_EQ(f["CityObjects"].begin().key(), f["id"]);
    const std::string id = f["id"];
    EXPECT_EQ(f["CityObjects"][id]["attributes"], doc["CityObjects"][id]["attributes"]) << id;
    EXPECT_EQ(bad_indices(f), 0u) << f["id"];  // own vertices, from 0
    json one = f;
    one["transform"] = lines[0]["transform"];
    for (const auto& [type, a] : cityjson_type_areas(one)) sum[type] += a;
  }
  for (const auto& [type, a] : store_type_areas(model)) EXPECT_NEAR(sum[type], a, 0.01) << type;
  if (can_ajv()) {
    std::string out;
    fx::write_text(dir + "/seq_header.city.json", lines[0].dump());
    EXPECT_EQ(ajv(dir + "/seq_header.city.json", &out), 0) << out;
    for (size_t k = 1; k < lines.size(); ++k) {
      fx::write_text(dir + "/seq_feature.json", lines[k].dump());
      EXPECT_EQ(ajv(dir + "/seq_feature.json", &out, "cityjsonfeature"), 0) << lines[k]["id"] << out;
    }
  }
  if (auto invalid = test::val3dity_invalid(written[0])) EXPECT_TRUE(invalid->empty()) << (*invalid)[0];
}

TEST_F(CityJson, Val3dityFindsEveryBuildingValid) {
  const auto invalid = test::val3dity_invalid(path);
  C3D_NEED(invalid, "../shared/tools/val3dity not found");
  EXPECT_TRUE(invalid->empty()) << (*invalid)[0];
}
