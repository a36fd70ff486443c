// CityGML 2.0 export: schema-valid (xmllint against the CityGML 2.0 XSDs), every
// xlink resolves, every polygon has a gml:id, areas read back from gen attributes.
#include <gtest/gtest.h>

#include <map>
#include <regex>
#include <set>

#include "ifc_citygml/export.h"
#include "tests/export_checks.h"
#include "tests/export_fixtures.h"
#include "tests/test_support.h"

using namespace c3d;
namespace fx = c3d::fixture;
using namespace c3d::check;

namespace {

class CityGml : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = test::temp_dir("export_citygml");
    path = dir + "/buildings.gml";
    write_citygml(model, path);
    xml = fx::read_text(path);
  }
  BatchModel model = fx::sample_batch();
  std::string dir, path, xml;
};

}  // namespace

TEST_F(CityGml, SchemaValid) {
  if (!can_xmllint()) GTEST_SKIP() << "xmllint or ../shared/schemas missing";
  std::string out;
  EXPECT_EQ(xmllint(path, &out), 0) << out;
}

TEST_F(CityGml, BrokenFileFailsSchema) {
  if (!can_xmllint()) GTEST_SKIP() << "xmllint or ../shared/schemas missing";
  std::string bad = xml;
  bad.replace(bad.find("<bldg:measuredHeight"), 0, "<bldg:noSuchElement/>");
  fx::write_text(dir + "/bad.gml", bad);
  std::string out;
  EXPECT_NE(xmllint(dir + "/bad.gml", &out), 0) << out;
}

TEST_F(CityGml, XlinksResolveAndPolygonsHaveIds) {
  EXPECT_TRUE(dangling_xlinks(xml).empty());
  size_t polygons = 0, with_id = 0;
  for (size_t p = xml.find("<gml:Polygon"); p != std::string::npos; p = xml.find("<gml:Polygon", p + 1)) {
    ++polygons;
    with_id += xml.compare(p, 21, "<gml:Polygon gml:id=\"") == 0;
  }
  EXPECT_GT(polygons, 0u);
  EXPECT_EQ(polygons, with_id);
  // The solid reuses element polygons: the attached houses' faces are all xlinks.
  EXPECT_NE(xml.find("xlink:href=\"#c3d_P-002_b1_e5_f0\""), std::string::npos);
  // Negative: a dangling reference is caught.
  std::string bad = xml;
  bad.replace(bad.find("xlink:href=\"#") + 13, 4, "zzzz");
  EXPECT_EQ(dangling_xlinks(bad).size(), 1u);
}

TEST_F(CityGml, GeoreferencedWorldCoordinates) {
  EXPECT_NE(xml.find("srsName=\"urn:ogc:def:crs:EPSG::32748\""), std::string::npos);
  // Ground corner (0,0,0) of the gable house = frame origin, in millimetres.
  EXPECT_NE(xml.find("789012.000 9237654.000 700.000"), std::string::npos);
  EXPECT_NE(xml.find("<core:name>P-001</core:name>"), std::string::npos);
  EXPECT_NE(xml.find("<gen:value>Hak Guna Bangunan</gen:value>"), std::string::npos);
}

TEST_F(CityGml, PartsOnlyForSeveralRoofLevels) {
  EXPECT_NE(xml.find("gml:id=\"c3d_P-004_b1_part0\""), std::string::npos);
  EXPECT_NE(xml.find("gml:id=\"c3d_P-004_b1_part1\""), std::string::npos);
  EXPECT_EQ(xml.find("c3d_P-001_b1_part"), std::string::npos);
  EXPECT_NE(xml.find("<gen:value>party_wall</gen:value>"), std::string::npos);
}

TEST_F(CityGml, ElementAreasReadBack) {
  // Each boundary surface: gml:id="c3d_<building>_e<k>" ... area attribute.
  std::regex surf_re(
      "<bldg:(\\w+Surface) gml:id=\"c3d_([^\"]+)_e(\\d+)\">[\\s\\S]*?"
      "<gen:doubleAttribute name=\"area\"><gen:value>([0-9.]+)</gen:value>");
  std::map<std::string, double> read;
  for (std::sregex_iterator it(xml.begin(), xml.end(), surf_re), end; it != end; ++it)
    read[(*it)[2].str() + "/" + (*it)[3].str()] = std::stod((*it)[4]);
  size_t n = 0;
  for (const auto& r : model.results)
    for (const auto& b : r.buildings)
      for (size_t e = 0; e < b.elements.size(); ++e, ++n) {
        auto it = read.find(b.id + "/" + std::to_string(e));
        ASSERT_NE(it, read.end()) << b.id << " element " << e;
        EXPECT_NEAR(it->second, b.elements[e].area, 0.01) << b.id << " element " << e;
      }
  EXPECT_EQ(read.size(), n);
}
