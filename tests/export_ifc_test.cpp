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
#else
TEST_F(Ifc, IfcPlusPlusReadsItStrictly) { GTEST_SKIP() << "libifcplusplus-dev not found at configure time"; }
#endif

TEST_F(Ifc, WebIfcMeshesAndQuantities) {
  if (fx::js_dir().empty()) GTEST_SKIP() << "tests/js/node_modules (npm install) or node missing";
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
