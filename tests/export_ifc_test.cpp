// IFC4 export: read back by two independent readers where installed (IFC++ — strict on
// attribute counts and references — and npm web-ifc — geometry and quantities),
// GlobalIds valid, unique and reproducible, quantities equal the model's areas.
#include <gtest/gtest.h>

#include <map>
#include <nlohmann/json.hpp>
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

class Ifc : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = test::temp_dir("export_ifc");
    path = dir + "/buildings.ifc";
    write_ifc(model, path);
    text = fx::read_text(path);
  }
  // Element tag "<building>/e<k>" -> reported area.
  std::map<std::string, double> expected_areas() const {
    std::map<std::string, double> a;
    for (const auto& r : model.results)
      for (const auto& b : r.buildings)
        for (size_t e = 0; e < b.elements.size(); ++e)
          a[b.id + "/e" + std::to_string(e)] = b.elements[e].area;
    return a;
  }
  BatchModel model = fx::sample_batch();
  std::string dir, path, text;
};

// Known answers of the fixture: attached_a (2 storeys, eave 6 m) has its upper
// exterior wall (from 4 m) and its roof on the upper floor; two_levels (2 storeys
// by its eave of 3.5 m) its roofs and the step wall (from 3.5 m) there; the rest,
// and every element of the one-storey houses, is on the ground floor.
std::map<std::string, std::string> expected_storeys(const BatchModel& model) {
  std::map<std::string, std::string> s;
  for (const auto& r : model.results)
    for (const auto& b : r.buildings)
      for (size_t e = 0; e < b.elements.size(); ++e) s[b.id + "/e" + std::to_string(e)] = "Ground floor";
  for (const char* tag : {"P-002_b1/e0", "P-002_b1/e4", "P-004_b1/e0", "P-004_b1/e1", "P-004_b1/e6"})
    s[tag] = "Floor 1";
  return s;
}

}  // namespace

TEST_F(Ifc, HeaderAndGeoreference) {
  EXPECT_EQ(text.rfind("ISO-10303-21;\nHEADER;", 0), 0u);
  EXPECT_NE(text.find("FILE_SCHEMA(('IFC4'));"), std::string::npos);
  EXPECT_NE(text.find("IFCPROJECTEDCRS('EPSG:32748'"), std::string::npos);
  EXPECT_NE(text.find(",789012.,9237654.,700.,1.,0.,1.)"), std::string::npos);
  EXPECT_NE(text.find("IFCSIUNIT(*,.AREAUNIT.,$,.SQUARE_METRE.)"), std::string::npos);
  EXPECT_NE(text.find(".USERDEFINED.)"), std::string::npos);  // party walls
  EXPECT_NE(text.find(".CEILING.)"), std::string::npos);
}

TEST_F(Ifc, GlobalIdsValidUniqueReproducible) {
  std::regex gid_re("^#\\d+=IFC\\w+\\('([^']*)'");
  std::set<std::string> ids;
  size_t n = 0;
  std::istringstream is(text);
  for (std::string line; std::getline(is, line);) {
    std::smatch m;
    if (!std::regex_search(line, m, gid_re) || line.find("IFCPROPERTYSINGLEVALUE") != std::string::npos ||
        line.find("IFCQUANTITY") != std::string::npos || line.find("IFCPROJECTEDCRS") != std::string::npos ||
        line.find("IFCGEOMETRICREPRESENTATION") != std::string::npos || line.find("IFCPERSON") != std::string::npos)
      continue;
    const std::string g = m[1];
    ++n;
    ASSERT_EQ(g.size(), 22u) << line;
    ASSERT_TRUE(g[0] >= '0' && g[0] <= '3') << line;
    ASSERT_EQ(g.find_first_not_of("0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz_$"),
              std::string::npos) << line;
    ids.insert(g);
  }
  EXPECT_GT(n, 50u);
  EXPECT_EQ(ids.size(), n);
  write_ifc(model, dir + "/again.ifc");
  std::string again = fx::read_text(dir + "/again.ifc");
  auto data = [](const std::string& s) { return s.substr(s.find("DATA;")); };
  EXPECT_EQ(data(again), data(text));
}

#ifdef C3D_HAVE_IFCPP
TEST_F(Ifc, IfcPlusPlusReadsItStrictly) {
  IfcppRead r = read_with_ifcpp(text);
  EXPECT_EQ(r.problems, 0) << r.messages;
  EXPECT_GT(r.entities, 100u);
  auto expected = expected_areas();
  for (const auto& res : model.results)  // IfcRoof carries the sum of its slabs
    for (const auto& b : res.buildings) {
      double roof = 0;
      for (const auto& e : b.elements) roof += e.type == ElementType::Roof ? e.area : 0;
      EXPECT_NEAR(r.gross[b.id + "/roof"], roof, 0.01) << b.id;
      r.gross.erase(b.id + "/roof");
    }
  ASSERT_EQ(r.gross.size(), expected.size());
  for (const auto& [tag, a] : expected) EXPECT_NEAR(r.gross[tag], a, 0.01) << tag;
}

TEST_F(Ifc, IfcPlusPlusCatchesBrokenFiles) {
  std::string bad = text;  // IfcWall with one attribute missing
  size_t p = bad.find("IFCWALL(");
  ASSERT_NE(p, std::string::npos);
  size_t end = bad.find(".SOLIDWALL.)", p);
  bad.replace(bad.rfind(',', end), end + 11 - bad.rfind(',', end), "");
  IfcppRead r = read_with_ifcpp(bad);
  EXPECT_GT(r.problems, 0) << "wrong attribute count not reported";
  bad = text;  // dangling reference
  p = bad.find("IFCRELCONTAINEDINSPATIALSTRUCTURE(");
  size_t hash = bad.find(",#", p);
  bad.replace(hash + 2, 0, "99999");
  IfcppRead r2 = read_with_ifcpp(bad);
  EXPECT_GT(r2.problems, 0) << "dangling reference not reported";
}

TEST_F(Ifc, IfcPlusPlusSeesStoreysAndIsExternal) {
  // One storey per building and no IsExternal before.
  IfcppRead r = read_with_ifcpp(text);
  for (const auto& res : model.results)
    for (const auto& b : res.buildings) EXPECT_EQ(r.storeys[b.id], b.storeys) << b.id;
  const auto expected = expected_storeys(model);
  ASSERT_EQ(r.storey.size(), expected.size());
  for (const auto& [tag, name] : expected) EXPECT_EQ(r.storey[tag], name) << tag;
  ASSERT_EQ(r.is_external.size(), expected.size());
  for (const auto& [tag, ext] : r.is_external) EXPECT_TRUE(ext) << tag;
}
#else
TEST_F(Ifc, IfcPlusPlusReadsItStrictly) {
  C3D_NEED(false, "libifcplusplus-dev not found at configure time");
}
#endif

TEST_F(Ifc, WebIfcMeshesAndQuantities) {
  C3D_NEED(!fx::js_dir().empty(), "tests/js/node_modules (npm install) or node missing");
  std::string out;
  ASSERT_EQ(fx::sh("node " + fx::js_dir() + "/ifc_check.js " + path + " 2>/dev/null", &out), 0) << out;
  auto doc = nlohmann::json::parse(out.substr(out.find('{')));
  auto expected = expected_areas();
  ASSERT_EQ(doc["elements"].size(), expected.size());
  for (const auto& e : doc["elements"]) {
    std::string tag = e["tag"];
    EXPECT_EQ(e["meshes"], 1) << tag;
    EXPECT_GT(e["triangles"].get<int>(), 0) << tag;
    EXPECT_NEAR(e["mesh_area"].get<double>(), expected[tag], 0.01) << tag;
  }
  std::map<std::string, double> gross;
  for (const auto& q : doc["quantities"])
    if (q["name"] == "GrossArea" || q["name"] == "GrossSideArea") gross[q["tag"]] = q["value"];
  ASSERT_EQ(gross.size(), expected.size());
  for (const auto& [tag, a] : expected) EXPECT_NEAR(gross[tag], a, 0.01) << tag;
}

// The IFC4 common property set of each kind of element, with the properties we
// write (all defined there by IFC4 ADD2 TC1), and what web-ifc reads of them.
TEST_F(Ifc, WebIfcStoreysAndCommonPropertySets) {
  C3D_NEED(!fx::js_dir().empty(), "tests/js/node_modules (npm install) or node missing");
  std::string out;
  ASSERT_EQ(fx::sh("node " + fx::js_dir() + "/ifc_check.js " + path + " 2>/dev/null", &out), 0) << out;
  auto doc = nlohmann::json::parse(out.substr(out.find('{')));
  std::map<std::string, const Building*> building;
  std::map<std::string, const Element*> element;
  for (const auto& r : model.results)
    for (const auto& b : r.buildings) {
      building[b.id] = &b;
      for (size_t e = 0; e < b.elements.size(); ++e) element[b.id + "/e" + std::to_string(e)] = &b.elements[e];
    }
  // Storeys: Building::storeys of them, equal height from the terrain to the eave.
  ASSERT_EQ(doc["buildings"].size(), building.size());
  for (const auto& jb : doc["buildings"]) {
    const Building& b = *building.at(jb["name"]);
    ASSERT_EQ(jb["storeys"].size(), size_t(b.storeys)) << b.id;
    std::map<std::string, double> elevation;
    for (const auto& s : jb["storeys"]) elevation[s["name"]] = s["elevation"];
    const double h = b.eave_height / b.storeys;
    EXPECT_NEAR(elevation["Ground floor"], b.terrain_z, 1e-4) << b.id;
    if (b.storeys > 1) EXPECT_NEAR(elevation["Floor 1"], b.terrain_z + h, 1e-4) << b.id;
  }
  // Every element on its storey, where it was (storey placements applied).
  const auto expected = expected_storeys(model);
  ASSERT_EQ(doc["elements"].size(), expected.size());
  for (const auto& e : doc["elements"]) {
    const std::string tag = e["tag"];
    EXPECT_EQ(e["storey"], expected.at(tag)) << tag;
    double zmin = 1e300;
    for (const auto& f : element.at(tag)->faces)
      for (const auto& p : f.ring) zmin = std::min(zmin, p.z());
    EXPECT_NEAR(e["min_z"].get<double>(), zmin, 1e-3) << tag;
  }
  // Common property sets: IsExternal on every element (party walls included),
  // a roof slab's PitchAngle in radians, the IfcRoof's and the building's sets.
  const std::map<std::string, std::set<std::string>> defined = {
      {"Pset_WallCommon", {"IsExternal"}},
      {"Pset_SlabCommon", {"IsExternal", "PitchAngle"}},
      {"Pset_CoveringCommon", {"IsExternal"}},
      {"Pset_RoofCommon", {"IsExternal"}},
      {"Pset_BuildingCommon", {"BuildingID", "NumberOfStoreys"}}};
  std::map<std::string, std::map<std::string, nlohmann::json>> common;  // tag -> "pset.name" -> value
  for (const auto& p : doc["properties"]) {
    const std::string pset = p["pset"];
    if (pset.rfind("Pset_", 0) != 0) continue;
    ASSERT_TRUE(defined.count(pset)) << pset;
    EXPECT_TRUE(defined.at(pset).count(p["name"])) << pset << "." << p["name"];
    common[p["tag"]][pset + "." + p["name"].get<std::string>()] = p["value"];
  }
  for (const auto& [tag, el] : element) {
    const char* pset = el->type == ElementType::OuterCeiling ? "Pset_CoveringCommon"
                       : (el->type == ElementType::Wall || el->type == ElementType::PartyWall) ? "Pset_WallCommon"
                                                                                               : "Pset_SlabCommon";
    EXPECT_EQ(common[tag][std::string(pset) + ".IsExternal"], true) << tag;
    if (el->type == ElementType::Roof)
      EXPECT_NEAR(common[tag]["Pset_SlabCommon.PitchAngle"].get<double>(), el->slope_deg * M_PI / 180, 1e-6) << tag;
  }
  for (const auto& [id, b] : building) {
    EXPECT_EQ(common[id + "/roof"]["Pset_RoofCommon.IsExternal"], true) << id;
    EXPECT_EQ(common[id]["Pset_BuildingCommon.NumberOfStoreys"], b->storeys) << id;
    EXPECT_EQ(common[id]["Pset_BuildingCommon.BuildingID"], id) << id;
  }
}
