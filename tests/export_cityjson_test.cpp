// CityJSON 2.0 export: schema-valid (ajv with the 2.0.2 schema), every vertex index in
// range (checked here, the schema cannot), areas per semantic surface read back from
// the geometry, and the read-back model validates.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

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

class CityJson : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = test::temp_dir("export_cityjson");
    path = dir + "/buildings.city.json";
    write_cityjson(model, path);
    doc = json::parse(fx::read_text(path));
  }
  BatchModel model = fx::sample_batch();
  std::string dir, path;
  json doc;
};

}  // namespace

TEST_F(CityJson, SchemaValid) {
  if (!can_ajv()) GTEST_SKIP() << "tests/js/node_modules (npm) or ../shared/schemas missing";
  std::string out;
  EXPECT_EQ(ajv(path, &out), 0) << out;
}

TEST_F(CityJson, BrokenFileFailsSchema) {
  if (!can_ajv()) GTEST_SKIP() << "tests/js/node_modules (npm) or ../shared/schemas missing";
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
  EXPECT_EQ(doc["CityObjects"]["P-004_b1"]["children"].size(), 2u);
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
