// CityGML 2.0 and 3.0 export: schema-valid (xmllint against the CityGML 2.0 / 3.0
// XSDs), every xlink resolves, every polygon has a gml:id, areas read back from
// the generic attributes.
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

// The gable house with an LoD 1.2 prism and an LoD 1.3 block (by hand, as the
// reconstruction will give them) and a roof type.
BatchModel with_lower_lod(BatchModel m) {
  Building& g = m.results[0].buildings[0];
  for (auto [lod, h] : {std::pair{Lod::Lod12, 4.5}, {Lod::Lod13, 5.25}}) {
    LodShell l;
    l.lod = lod;
    l.faces = test::box_shell({0, 0, 0}, {10, 8, h});
    l.face_types.assign(l.faces.size(), ElementType::Wall);
    g.lower_lods.push_back(l);
  }
  g.attributes.roof_type = "slanted";
  g.attributes.roof_z_50p = 4.5;
  return m;
}

// Parameter: the CityGML version.
class CityGml : public ::testing::TestWithParam<int> {
 protected:
  void SetUp() override {
    dir = test::temp_dir("export_citygml");
    path = dir + "/buildings.gml";
    write_citygml(model, path, GetParam());
    xml = fx::read_text(path);
  }
  BatchModel model = with_lower_lod(fx::sample_batch());
  std::string dir, path, xml;
};

}  // namespace

TEST_P(CityGml, SchemaValid) {
  C3D_NEED(can_xmllint(), "xmllint or ../shared/schemas missing");
  std::string out;
  EXPECT_EQ(xmllint(path, &out, GetParam()), 0) << out;
}

TEST_P(CityGml, BrokenFileFailsSchema) {
  C3D_NEED(can_xmllint(), "xmllint or ../shared/schemas missing");
  std::string bad = xml;
  bad.replace(bad.find("<bldg:storeysAboveGround"), 0, "<bldg:noSuchElement/>");
  fx::write_text(dir + "/bad.gml", bad);
  std::string out;
  EXPECT_NE(xmllint(dir + "/bad.gml", &out, GetParam()), 0) << out;
}

TEST_P(CityGml, XlinksResolveAndPolygonsHaveIds) {
  EXPECT_TRUE(dangling_xlinks(xml).empty());
  size_t polygons = 0, with_id = 0;
  for (size_t p = xml.find("<gml:Polygon"); p != std::string::npos; p = xml.find("<gml:Polygon", p + 1)) {
    ++polygons;
    with_id += xml.compare(p, 21, "<gml:Polygon gml:id=\"") == 0;
  }
  EXPECT_GT(polygons, 0u);
  EXPECT_EQ(polygons, with_id);
  // The solid reuses element polygons: the attached houses' faces are all xlinks.
  EXPECT_NE(xml.find("xlink:href=\"#c3d_P-002_b1_s4\""), std::string::npos);
  // Negative: a dangling reference is caught.
  std::string bad = xml;
  bad.replace(bad.find("xlink:href=\"#") + 13, 4, "zzzz");
  EXPECT_EQ(dangling_xlinks(bad).size(), 1u);
}

TEST_P(CityGml, GeoreferencedWorldCoordinates) {
  EXPECT_NE(xml.find("srsName=\"urn:ogc:def:crs:EPSG::32748\""), std::string::npos);
  // Ground corner (0,0,0) of the gable house = frame origin, in millimetres.
  EXPECT_NE(xml.find("789012.000 9237654.000 700.000"), std::string::npos);
  EXPECT_NE(xml.find(GetParam() == 3 ? "urn:cadastre3d:la_spatialunit:P-001</core:targetResource>"
                                     : "<core:name>P-001</core:name>"),
            std::string::npos);
  if (GetParam() == 3) EXPECT_NE(xml.find("xmlns:gml=\"http://www.opengis.net/gml/3.2\""), std::string::npos);
  EXPECT_NE(xml.find("<gen:value>Hak Guna Bangunan</gen:value>"), std::string::npos);
}

TEST_P(CityGml, PartsOnlyForSeveralRoofLevels) {
  EXPECT_NE(xml.find("gml:id=\"c3d_P-004_b1_part0\""), std::string::npos);
  EXPECT_NE(xml.find("gml:id=\"c3d_P-004_b1_part1\""), std::string::npos);
  EXPECT_EQ(xml.find("c3d_P-001_b1_part"), std::string::npos);
  EXPECT_NE(xml.find("<gen:value>party_wall</gen:value>"), std::string::npos);
}

TEST_P(CityGml, ElementAreasReadBack) {
  std::map<std::string, double> read = citygml_areas(xml);
  size_t n = 0;
  for (const auto& r : model.results)
    for (const auto& b : r.buildings)
      for (size_t e = 0; e < b.elements.size(); ++e, ++n) {
        auto it = read.find(b.id + "/e" + std::to_string(e));
        ASSERT_NE(it, read.end()) << b.id << " element " << e;
        EXPECT_NEAR(it->second, b.elements[e].area, 0.01) << b.id << " element " << e;
      }
  EXPECT_EQ(read.size(), n);
}

TEST_P(CityGml, EachPolygonOnceSummingToTheElementTotals) {
  // An element's surface holds its faces in the solid and what lies outside it
  // (the overhang), the solid refers to them: summed over the file, the LoD 2
  // polygons give the element totals. Before, the solid's clipped roofs were
  // polygons of their own beside the whole roofs.
  double lod2 = 0, lod1 = 0, elements = 0;
  for (const auto& [id, a] : citygml_polygon_areas(xml)) (id.find("_lod1s") != std::string::npos ? lod1 : lod2) += a;
  for (const auto& r : model.results)
    for (const auto& b : r.buildings)
      for (const auto& e : b.elements) elements += e.area;
  EXPECT_NEAR(lod2, elements, 0.01);
  // The highest lower LoD is the lod1Solid (one solid per CityGML LoD).
  EXPECT_NEAR(lod1, 2 * 80 + 2 * (10 + 8) * 5.25, 1e-6);
  EXPECT_NE(xml.find(GetParam() == 3 ? "<core:lod1Solid>" : "<bldg:lod1Solid>"), std::string::npos);
  EXPECT_NE(xml.find("<gen:value>LoD 1.3</gen:value>"), std::string::npos);
  EXPECT_NE(xml.find("<gen:value>slanted</gen:value>"), std::string::npos);
  EXPECT_NE(xml.find("704.500"), std::string::npos);  // roofHeight50p, world z
}

INSTANTIATE_TEST_SUITE_P(Version, CityGml, ::testing::Values(2, 3),
                         [](const auto& info) { return "v" + std::to_string(info.param); });
