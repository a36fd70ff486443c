// OBJ per parcel (groups per element, triangle areas = element areas) and STEP
// solids per building (closed B-rep written by OpenCASCADE).
#include <gtest/gtest.h>

#include <BRepAdaptor_Surface.hxx>
#include <BRepBndLib.hxx>
#include <BRepGProp.hxx>
#include <Bnd_Box.hxx>
#include <GProp_GProps.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <Interface_Static.hxx>
#include <STEPControl_Controller.hxx>
#include <STEPControl_Reader.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <fstream>
#include <set>
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

// The OBJ is local (float32 readers keep local metres to 0.1 mm but world UTM
// northings only to the metre); P-001.offset.json beside it gives the offset and
// CRS, P-001.prj the CRS for GIS tools: a float32 reader adding the offset in
// double gets the model's world coordinates to the millimetre.
TEST(ExportObj, OffsetFileBesideEachObjGivesWorldCoordinates) {
  BatchModel m = fx::sample_batch();
  std::string dir = test::temp_dir("export_obj_georef");
  for (const auto& obj : write_obj_per_parcel(m, dir)) {
    std::filesystem::path json = obj, prj = obj;
    json.replace_extension(".offset.json");
    prj.replace_extension(".prj");
    ASSERT_TRUE(std::filesystem::exists(json)) << json;
    EXPECT_NE(fx::read_text(prj.string()).find("WGS_1984_UTM_Zone_48S"), std::string::npos) << prj;
    auto g = nlohmann::json::parse(fx::read_text(json.string()));
    EXPECT_EQ(g["obj"], std::filesystem::path(obj).filename().string());
    EXPECT_EQ(g["crs"], "EPSG:32748");
    EXPECT_EQ(g["world"], "local + offset");
    const Vec3 offset(g["offset"][0], g["offset"][1], g["offset"][2]);
    EXPECT_EQ(offset, m.frame.origin);
  }
  // P-004: every vertex, read as float32 plus the offset, is a model vertex (world) to 1 mm.
  const Building& b = m.results[3].buildings[0];
  std::vector<Vec3> world;
  for (const auto& e : b.elements)
    for (const auto& f : e.faces)
      for (const auto& p : f.ring) world.push_back(m.frame.to_world(p));
  std::istringstream is(fx::read_text(dir + "/P-004.obj"));
  size_t n = 0;
  for (std::string line; std::getline(is, line);) {
    if (line.rfind("v ", 0) != 0) continue;
    const char* c = line.c_str() + 2;
    char* end = nullptr;
    float x = std::strtof(c, &end), y = std::strtof(end, &end), z = std::strtof(end, &end);
    const Vec3 w = Vec3(x, y, z) + m.frame.origin;
    double best = 1e300;
    for (const auto& p : world) best = std::min(best, (p - w).norm());
    EXPECT_LT(best, 1e-3) << line;
    ++n;
  }
  EXPECT_GT(n, 20u);
  // Why not world coordinates: a float32 northing near 9.2e6 m is on a 1 m grid.
  const double northing = m.frame.origin.y() + 0.4;
  EXPECT_GT(std::abs(double(float(northing)) - northing), 0.1);
}

// A STEP file as OpenCASCADE reads it, in metres: its volume, box and
// the kinds of surface its faces lie on.

struct StepReadBack {
  double volume = 0;
  Bnd_Box box;
  std::set<GeomAbs_SurfaceType> surfaces;  // the kinds of its faces' surfaces
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
  for (TopExp_Explorer f(shape, TopAbs_FACE); f.More(); f.Next())
    r.surfaces.insert(BRepAdaptor_Surface(TopoDS::Face(f.Current())).GetType());
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

// Curved buildings go to STEP on their exact surfaces: a vault's cylinder, a
// dome's sphere, a cone, an onion's B-spline turned about its axis (read
// back as a surface of revolution), a free-form roof's B-spline, with the
// store's volume within 0.1 %
// (the store takes its volume from the same exact shape) and the truth's
// within 2 %. The planar gable stays planes.
TEST(ExportStep, CurvedBuildingsOnTheirExactSurfaces) {
  const std::string dir = test::temp_dir("export_step_curved");
  ASSERT_EQ(test::sample_and_batch(dir, "--curved --parcels 20 --seed 11", "--formats step"), "");
  const auto truth = nlohmann::json::parse(std::ifstream(dir + "/town/truth.json"));
  const auto summary = nlohmann::json::parse(std::ifstream(dir + "/out/summary.json"));
  const std::map<std::string, GeomAbs_SurfaceType> surface = {
      {"vault", GeomAbs_Cylinder},      {"ground_vault", GeomAbs_Cylinder}, {"dome", GeomAbs_Sphere},
      {"shallow_dome", GeomAbs_Sphere}, {"cone", GeomAbs_Cone},             {"onion", GeomAbs_SurfaceOfRevolution},
      {"dome_on_flat", GeomAbs_Sphere}, {"gable", GeomAbs_Plane},   {"saddle", GeomAbs_BSplineSurface},
      {"wave", GeomAbs_BSplineSurface}};
  int curved = 0;
  for (size_t i = 0; i < truth["parcels"].size(); ++i) {
    const std::string layout = truth["parcels"][i]["layout"];
    if (summary["parcels"][i]["status"] != "ok") continue;  // an onion whose drum no scan saw
    const auto& b = summary["parcels"][i]["buildings"][0];
    const StepReadBack back = read_step(dir + "/out/step/" + b["building_id"].get<std::string>() + ".step");
    EXPECT_TRUE(back.surfaces.count(surface.at(layout))) << layout;
    if (layout == "gable") {
      EXPECT_EQ(back.surfaces, std::set<GeomAbs_SurfaceType>{GeomAbs_Plane});
      continue;
    }
    ++curved;
    EXPECT_NEAR(back.volume / b["volume_m3"].get<double>(), 1, 0.001) << layout;
    EXPECT_NEAR(back.volume / truth["parcels"][i]["buildings"][0]["volume_m3"].get<double>(), 1, 0.02) << layout;
  }
  EXPECT_GE(curved, 16);
}
