// batch --mesh (issue 50): every modelled building's points meshed at four
// levels, the files beside the store with their SHA-256, the closed level
// valid by val3dity, every glTF by the Khronos validator, and the element
// model checked against the hull.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include <nlohmann/json.hpp>

#include "cadastre/batch/building_meshes.h"
#include "core/geometry/geometry.h"
#include "tests/batch_e2e_support.h"
#include "tests/report_checks.h"
#include "tests/test_support.h"

namespace c3d {
namespace {

namespace fs = std::filesystem;

// A binary PLY as ladder files write it (float32 vertices, uchar + 3 int32 faces) as OBJ text.
std::string obj_of_ply(const std::string& ply) {
  const std::string bytes = e2e::read_file(ply);
  const size_t body = bytes.find("end_header\n") + 11;
  const size_t nv = std::stoul(bytes.substr(bytes.find("element vertex ") + 15));
  const size_t nf = std::stoul(bytes.substr(bytes.find("element face ") + 13));
  EXPECT_EQ(bytes.size(), body + 12 * nv + 13 * nf) << ply;
  std::string obj;
  for (size_t i = 0; i < nv; ++i) {
    float v[3];
    std::memcpy(v, bytes.data() + body + 12 * i, sizeof v);
    obj += "v " + std::to_string(v[0]) + " " + std::to_string(v[1]) + " " + std::to_string(v[2]) + "\n";
  }
  obj += "o hull\n";
  for (size_t i = 0; i < nf; ++i) {
    int32_t t[3];
    std::memcpy(t, bytes.data() + body + 12 * nv + 13 * i + 1, sizeof t);
    obj += "f " + std::to_string(t[0] + 1) + " " + std::to_string(t[1] + 1) + " " + std::to_string(t[2] + 1) + "\n";
  }
  return obj;
}

std::string sha256sum(const std::string& path) {  // coreutils': a judge apart from ours
  return test::shell("sha256sum '" + path + "' | cut -c1-64 | tr -d '\\n'");
}

// Every level's files exist with the SHA-256 the store holds, and every
// level 1 is a valid solid by val3dity; *glbs gathers the glTF files.
void expect_files_as_stored(e2e::Sqlite& db, const std::string& out, std::string* glbs) {
  std::vector<e2e::Row> files;
  ASSERT_TRUE(db.query("SELECT ply, ply_sha256, glb, glb_sha256, picture, picture_sha256, level FROM "
                       "building_mesh_level ORDER BY building_fid, level",
                       &files))
      << db.error();
  for (const auto& f : files) {
    for (int k = 0; k < 6; k += 2) {
      ASSERT_FALSE(f[size_t(k)].s.empty()) << "every level has faces here";
      const std::string path = out + "/" + f[size_t(k)].s;
      ASSERT_TRUE(fs::exists(path)) << path;
      EXPECT_EQ(sha256sum(path), f[size_t(k) + 1].s) << path;
    }
    *glbs += " " + out + "/" + f[2].s;
    if (f[6].d != 1) continue;
    const std::string obj = out + "/" + f[0].s + ".obj";
    std::ofstream(obj) << obj_of_ply(out + "/" + f[0].s);
    const fs::path val3dity = fs::path(C3D_SOURCE_DIR) / "../shared/tools/val3dity/val3dity";
    C3D_NEED(fs::exists(val3dity), "../shared/tools/val3dity missing");
    const std::string report = obj + ".json";
    test::shell(val3dity.string() + " --report " + report + " " + obj + " >/dev/null 2>&1");
    const auto judged = nlohmann::json::parse(std::ifstream(report));
    EXPECT_TRUE(judged.at("validity").get<bool>()) << obj << " by val3dity";
  }
}

// A six-parcel sample town through batch --mesh, once for the tests that read it.
struct MeshedTown {
  std::string dir, out, log;
  int rc = -1;
};

const MeshedTown& meshed_town() {
  static const MeshedTown t = [] {
    MeshedTown t;
    t.dir = test::temp_dir("batch_mesh");
    t.out = t.dir + "/out";
    e2e::make_town(t.dir + "/town", 6, 3);
    t.rc = test::run_cli(e2e::batch_args(t.dir + "/town", t.out) + " --mesh --formats cityjson", &t.log);
    return t;
  }();
  return t;
}

TEST(BatchMesh, EveryBuildingHasFourLevelsWithTheirFilesAndFigures) {
  const MeshedTown& t = meshed_town();
  ASSERT_TRUE(t.rc == 0 || t.rc == 3) << t.log;
  const std::string& out = t.out;
  e2e::Sqlite db(out + "/cadastre.gpkg");
  ASSERT_TRUE(db.ok()) << db.error();
  const double buildings = db.number("SELECT count(*) FROM building");
  ASSERT_GE(buildings, 4) << "most sample parcels hold a building";
  EXPECT_EQ(db.number("SELECT count(*) FROM building_mesh WHERE problem = ''"), buildings);
  EXPECT_EQ(db.number("SELECT count(*) FROM building_mesh_level"), 4 * buildings);
  // The sample's buildings are what their points say: the model agrees with the hull, none flagged.
  EXPECT_EQ(db.number("SELECT count(*) FROM building_mesh WHERE flag != ''"), 0);
  // A wrap lies outside its points: it holds the model and a little more (docs/meshes.md).
  EXPECT_EQ(db.number("SELECT count(*) FROM building_mesh WHERE volume_diff BETWEEN 0 AND 0.25 AND "
                      "abs(roof_area_diff) < 0.20"),
            buildings);
  // Level 4 runs through the points, level 3 keeps within a few spacings, level 1 is closed.
  EXPECT_EQ(db.number("SELECT count(*) FROM building_mesh_level WHERE level = 4 AND c2m_p95 < 0.01"), buildings);
  EXPECT_EQ(db.number("SELECT count(*) FROM building_mesh_level l JOIN building_mesh m USING (building_fid) "
                      "WHERE l.level = 3 AND l.c2m_p95 < 2 * m.spacing"),
            buildings);
  EXPECT_EQ(db.number("SELECT count(*) FROM building_mesh_level WHERE level = 1 AND closed = 1 AND manifold = 1 "
                      "AND faces <= 400"),
            buildings);
  // Level 3, at a tenth of level 4's faces, keeps every planar region of
  // level 4 and its extent within a centimetre (seed 002's table), on scans
  // at 3 cm noise; level 2 loses none either.
  EXPECT_EQ(db.number("SELECT count(*) FROM building_mesh_level l3 JOIN building_mesh_level l4 USING (building_fid) "
                      "WHERE l3.level = 3 AND l4.level = 4 AND l4.planar_regions >= 4 AND l3.faces <= l4.faces / 10 "
                      "AND l3.planar_regions = l4.planar_regions AND l3.planar_lost = 0 AND l3.extent_change <= 0.01 "
                      "AND l3.thickness > 0"),
            buildings);
  EXPECT_EQ(db.number("SELECT count(*) FROM building_mesh_level WHERE level = 2 AND planar_lost = 0"), buildings);

  std::string glbs;
  ASSERT_NO_FATAL_FAILURE(expect_files_as_stored(db, out, &glbs));

  const auto summary = nlohmann::json::parse(std::ifstream(out + "/summary.json"));
  size_t meshed = 0;
  for (const auto& p : summary["parcels"])
    for (const auto& b : p["buildings"]) {
      ASSERT_TRUE(b["mesh"].is_object()) << b["building_id"];
      EXPECT_EQ(b["mesh"]["levels"].size(), 4u);
      EXPECT_TRUE(b["mesh"]["model_vs_hull"]["flag"].is_null());
      EXPECT_GE(b["mesh"]["levels"][2]["planar_regions"]["count"].get<long>(), 1) << b["building_id"];
      ++meshed;
    }
  EXPECT_EQ(double(meshed), buildings);
  size_t pictures = 0;
  for (const auto& page : fs::directory_iterator(out + "/report/parcel")) {
    const std::string html = e2e::read_file(page.path().string());
    for (size_t at = html.find("<img src=\"../../mesh/"); at != std::string::npos;
         at = html.find("<img src=\"../../mesh/", at + 1))
      ++pictures;
  }
  EXPECT_EQ(double(pictures), 4 * buildings) << "a picture of each level on the parcel pages";

  const std::string js = std::string(C3D_SOURCE_DIR) + "/tests/js";
  C3D_NEED(fs::exists(js + "/node_modules/gltf-validator/package.json") && !test::shell("command -v node").empty(),
           "tests/js/node_modules/gltf-validator (scripts/setup.sh) or node missing");
  int node_rc = -1;
  const std::string judged = test::shell("node " + js + "/gltf_check.js" + glbs, &node_rc);
  EXPECT_EQ(node_rc, 0) << judged;
  size_t clean = 0;
  for (size_t at = judged.find(": 0 errors,"); at != std::string::npos; at = judged.find(": 0 errors,", at + 1))
    ++clean;
  EXPECT_EQ(double(clean), 4 * buildings) << judged;
}

// The parcel page's 3D view offers the element model and the four levels;
// a level chosen is drawn, and a click on it names the level.
TEST(BatchMesh, TheParcelViewSwitchesToTheMeshLevels) {
  const MeshedTown& t = meshed_town();
  ASSERT_TRUE(t.rc == 0 || t.rc == 3) << t.log;
  const std::string &dir = t.dir, &out = t.out;
  C3D_NEED(test::view_tools(), "node, tests/js/node_modules (puppeteer-core; scripts/setup.sh) or chromium missing");
  e2e::Sqlite db(out + "/cadastre.gpkg");
  ASSERT_TRUE(db.ok()) << db.error();
  std::vector<e2e::Row> parcels;
  ASSERT_TRUE(db.query("SELECT DISTINCT u.parcel_id FROM building b JOIN la_spatialunit u ON u.fid = b.spatialunit_id "
                       "ORDER BY u.parcel_id LIMIT 1", &parcels)) << db.error();
  ASSERT_EQ(parcels.size(), 1u);
  const std::string page = out + "/report/parcel/" + parcels[0][0].s + ".html";
  for (const char* level : {"1", "3"}) {
    const auto view = test::viewed(page, dir + "/level" + level + ".png",
                                   std::string("--unlit --level ") + level + " --click largest 0 --colours '#8fb8a8,#a0522d'");
    ASSERT_EQ(view.value("state", ""), "ready") << view.dump();
    EXPECT_TRUE(view["errors"].empty()) << view["errors"].dump();
    EXPECT_EQ(view["levels"], nlohmann::json({"0", "1", "2", "3", "4"}));
    EXPECT_GT(view["pixels"][0].get<int>(), 2000) << "the mesh drawn";
    EXPECT_EQ(view["pixels"][1].get<int>(), 0) << "the roofs hidden";
    EXPECT_EQ(view["pick"]["text"].get<std::string>().rfind(std::string("Mesh level ") + level + " of building", 0), 0u)
        << view["pick"].dump();
  }
}

TEST(BatchMesh, MergedShardsKeepTheirMeshFiles) {
  const std::string dir = test::temp_dir("shards");
  const std::string town = dir + "/town";
  e2e::make_town(town, 4, 5);
  std::string log;
  for (const char* k : {"1", "2"}) {
    const int rc = test::run_cli(e2e::batch_args(town, dir + "/shard" + k) + " --mesh --quiet --shard " + k + "/2", &log);
    ASSERT_TRUE(rc == 0 || rc == 3) << log;
  }
  const std::string out = dir + "/merged";
  const int rc = test::run_cli("merge --quiet --formats cityjson --out " + out + " " + dir + "/shard1/cadastre.gpkg " +
                                   dir + "/shard2/cadastre.gpkg",
                               &log);
  ASSERT_TRUE(rc == 0 || rc == 3) << log;
  e2e::Sqlite db(out + "/cadastre.gpkg");
  ASSERT_TRUE(db.ok()) << db.error();
  ASSERT_GT(db.number("SELECT count(*) FROM building"), 0);
  EXPECT_EQ(db.number("SELECT count(*) FROM building_mesh_level"), 4 * db.number("SELECT count(*) FROM building"));
  std::vector<e2e::Row> files;
  ASSERT_TRUE(db.query("SELECT glb, glb_sha256 FROM building_mesh_level", &files)) << db.error();
  for (const auto& f : files) EXPECT_EQ(sha256sum(out + "/" + f[0].s), f[1].s) << f[0].s;
}

// A scanned box: a flat roof 6 m up and four walls over a 10 x 8 m footprint,
// a point every 0.25 m.
ParcelScene scanned_box() {
  ParcelScene s;
  s.parcel = {Polygon2{{{-5, -5}, {15, -5}, {15, 13}, {-5, 13}}, {}}};
  for (double x = 0; x <= 10.001; x += 0.25)
    for (double y = 0; y <= 8.001; y += 0.25) s.roof_points.emplace_back(x, y, 6);
  for (double t = 0; t < 36; t += 0.25) {
    const Vec2 q = t < 10 ? Vec2(t, 0) : t < 18 ? Vec2(10, t - 10) : t < 28 ? Vec2(28 - t, 8) : Vec2(0, 36 - t);
    for (double z = 0.25; z < 6; z += 0.25) s.wall_points.emplace_back(q.x(), q.y(), z);
  }
  return s;
}

// The box modelled `height` m high: its faces as roof, walls and ground.
Building box_model(double height) {
  Building b;
  b.id = "box_b1";
  b.terrain_z = 0;
  for (const Face& f : test::box_shell(Vec3(0, 0, 0), Vec3(10, 8, height))) {
    const double nz = unit_normal(f).z();
    Element e;
    e.type = nz > 0.5 ? ElementType::Roof : nz < -0.5 ? ElementType::Ground : ElementType::Wall;
    e.faces = {f};
    e.area = area(f);
    b.elements.push_back(e);
  }
  b.volume = 80 * height;
  b.solid_valid = true;
  return b;
}

TEST(BatchMesh, AModelHigherThanItsPointsIsFlagged) {
  const ParcelScene scene = scanned_box();
  const std::string dir = test::temp_dir("flag");
  for (double height : {6.0, 9.0}) {
    ParcelResult r;
    r.buildings = {box_model(height)};
    mesh_buildings(scene, LocalFrame{}, {dir, DenseMethod::AdvancingFront}, r);
    const BuildingMesh& m = r.buildings[0].mesh;
    ASSERT_EQ(m.levels.size(), 4u) << m.problem;
    EXPECT_NEAR(m.model_volume, 80 * height, 1e-9) << "the volume under the roof";
    EXPECT_TRUE(m.levels[0].closed);
    if (height == 6.0) {
      EXPECT_NEAR(m.volume_diff, 0.0, 0.05) << "the hull of the box's points holds the box";
      EXPECT_NEAR(m.roof_area_diff, 0.0, 0.05);
      EXPECT_EQ(m.flag, "");
    } else {
      EXPECT_NEAR(m.volume_diff, -1.0 / 3, 0.05) << "the points stand 6 m high, the model 9 m";
      EXPECT_NE(m.flag.find("volume"), std::string::npos) << m.flag;
    }
  }
}

}  // namespace
}  // namespace c3d
