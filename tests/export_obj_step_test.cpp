// OBJ per parcel (groups per element, triangle areas = element areas) and STEP
// solids per building (closed B-rep written by OpenCASCADE).
#include <gtest/gtest.h>

#include <map>
#include <sstream>

#include "ifc_citygml/export.h"
#include "tests/export_fixtures.h"
#include "tests/test_support.h"

using namespace c3d;
namespace fx = c3d::fixture;

TEST(ExportObj, GroupsPerElementWithTheirAreas) {
  BatchModel m = fx::sample_batch();
  std::string dir = test::temp_dir("export_obj");
  auto files = write_obj_per_parcel(m, dir);
  ASSERT_EQ(files.size(), 4u);
  const Building& b = m.results[0].buildings[0];
  std::istringstream is(fx::read_text(dir + "/P-001.obj"));
  std::vector<Vec3> v;
  std::map<std::string, double> area;
  std::string line, group;
  while (std::getline(is, line)) {
    std::istringstream ls(line);
    std::string tag;
    ls >> tag;
    if (tag == "v") { Vec3 p; ls >> p.x() >> p.y() >> p.z(); v.push_back(p); }
    if (tag == "g") ls >> group;
    if (tag == "f") {
      long i[3];
      ls >> i[0] >> i[1] >> i[2];
      for (long k : i) ASSERT_TRUE(k >= 1 && k <= long(v.size())) << line;
      area[group] += 0.5 * (v[i[1] - 1] - v[i[0] - 1]).cross(v[i[2] - 1] - v[i[0] - 1]).norm();
    }
  }
  ASSERT_EQ(area.size(), b.elements.size());
  for (size_t e = 0; e < b.elements.size(); ++e) {
    std::string g = b.id + "_" + to_string(b.elements[e].type) + "_" + std::to_string(e);
    EXPECT_NEAR(area[g], b.elements[e].area, 0.01) << g;
  }
}

TEST(ExportStep, ClosedSolidPerBuilding) {
  BatchModel m = fx::sample_batch();
  std::string dir = test::temp_dir("export_step");
  auto files = write_step_per_building(m, dir);
  ASSERT_EQ(files.size(), 4u);
  for (const auto& f : files) {
    std::string s = fx::read_text(f);
    EXPECT_NE(s.find("ISO-10303-21"), std::string::npos) << f;
    EXPECT_NE(s.find("MANIFOLD_SOLID_BREP"), std::string::npos) << f;
    EXPECT_NE(s.find("CLOSED_SHELL"), std::string::npos) << f;
  }
}
