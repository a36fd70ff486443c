// OBJ per parcel (groups per element, triangle areas = element areas) and STEP
// solids per building (closed B-rep written by OpenCASCADE).
#include <gtest/gtest.h>

#include <BRepBndLib.hxx>
#include <BRepGProp.hxx>
#include <Bnd_Box.hxx>
#include <GProp_GProps.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <Interface_Static.hxx>
#include <STEPControl_Controller.hxx>
#include <STEPControl_Reader.hxx>
#include <TopoDS_Shape.hxx>

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

// A STEP file as OpenCASCADE reads it, in metres: its volume and box.
struct StepReadBack {
  double volume = 0;
  Bnd_Box box;
};

StepReadBack read_step(const std::string& path) {
  STEPControl_Controller::Init();
  Interface_Static::SetCVal("xstep.cascade.unit", "M");
  STEPControl_Reader reader;
  EXPECT_EQ(reader.ReadFile(path.c_str()), IFSelect_RetDone) << path;
  reader.TransferRoots();
  const TopoDS_Shape shape = reader.OneShape();
  GProp_GProps props;
  BRepGProp::VolumeProperties(shape, props);
  StepReadBack r;
  r.volume = props.Mass();
  BRepBndLib::Add(shape, r.box);
  return r;
}

TEST(ExportStep, ReadBackInMetresEqualsTheModel) {
  // The file once said millimetres over metre values: 05764_b1's 448.5 m3
  // read back as 4.49e-7. Volume and box are checked against the model.
  BatchModel m = fx::sample_batch();
  const std::string dir = test::temp_dir("export_step_units");
  const auto files = write_step_per_building(m, dir);
  ASSERT_FALSE(files.empty());
  EXPECT_NE(fx::read_text(files[0]).find("SI_UNIT($,.METRE.)"), std::string::npos);
  size_t k = 0;
  for (const auto& r : m.results)
    for (const auto& b : r.buildings) {
      if (b.solid.empty()) continue;
      ASSERT_LT(k, files.size());
      const StepReadBack back = read_step(files[k++]);
      EXPECT_NEAR(back.volume, b.volume, 1e-6 * b.volume + 1e-6) << b.id;
      double x0, y0, z0, x1, y1, z1;
      back.box.Get(x0, y0, z0, x1, y1, z1);
      Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
      for (const Face& f : b.solid)
        for (const Vec3& v : f.ring) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
      const double gap = back.box.GetGap() + 1e-6;  // OpenCASCADE pads the box by its tolerance
      EXPECT_NEAR(x1 - x0, hi.x() - lo.x(), 2 * gap) << b.id;
      EXPECT_NEAR(y1 - y0, hi.y() - lo.y(), 2 * gap) << b.id;
      EXPECT_NEAR(z1 - z0, hi.z() - lo.z(), 2 * gap) << b.id;
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
