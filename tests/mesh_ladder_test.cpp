// The mesh ladder (core/mesh, issue 50) on a scanned box house with known
// surfaces: flat roof and four walls sampled on a grid with Gaussian noise,
// no floor (a scan sees none).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/mesh/ladder.h"
#include "core/mesh/mesh_files.h"
#include "core/mesh/simplify.h"
#include "tests/test_support.h"

namespace c3d {
namespace {

constexpr double kStep = 0.25, kNoise = 0.01;  // m
constexpr double kWidth = 10, kDepth = 8, kHeight = 6;

// Roof and walls of a box, a point every kStep, each moved along its surface's
// normal by N(0, kNoise).
std::vector<Vec3> scanned_box(unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0, kNoise);
  std::vector<Vec3> pts;
  for (double x = 0; x <= kWidth + 1e-9; x += kStep)
    for (double y = 0; y <= kDepth + 1e-9; y += kStep) pts.emplace_back(x, y, kHeight + noise(rng));
  for (double z = 0; z < kHeight - 1e-9; z += kStep) {
    for (double x = 0; x <= kWidth + 1e-9; x += kStep) {
      pts.emplace_back(x, noise(rng), z);
      pts.emplace_back(x, kDepth + noise(rng), z);
    }
    for (double y = kStep; y < kDepth - 1e-9; y += kStep) {
      pts.emplace_back(noise(rng), y, z);
      pts.emplace_back(kWidth + noise(rng), y, z);
    }
  }
  return pts;
}

TEST(MeshLadder, SpacingOfAGridIsItsStep) {
  const PointSpacing s = point_spacing(scanned_box(1));
  EXPECT_NEAR(s.median, kStep, 0.03);
  EXPECT_GT(s.mean, 0.8 * kStep);
  EXPECT_LT(s.mean, 1.1 * kStep);
  EXPECT_LE(s.min, s.median);
  EXPECT_LE(s.p95, s.max);
}

// A noisy pitched roof: two 15 x 6 m planes at 30 degrees meeting on a ridge
// along x, a point every 0.1 m (jittered), each moved across its plane by N(0, sigma).
std::vector<Vec3> noisy_gable(double sigma, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> across(0, sigma);
  std::uniform_real_distribution<double> jitter(-0.03, 0.03);
  const double slope = std::tan(30 * M_PI / 180), cosine = std::cos(30 * M_PI / 180);
  std::vector<Vec3> pts;
  for (double x = 0; x <= 15 + 1e-9; x += 0.1)
    for (double y = -6; y <= 6 + 1e-9; y += 0.1) {
      const double px = x + jitter(rng), py = y + jitter(rng);
      const Vec3 normal = Vec3(0, py < 0 ? -slope : slope, 1) * cosine;
      pts.push_back(Vec3(px, py, 10 - slope * std::abs(py)) + across(rng) * normal);
    }
  return pts;
}

TEST(MeshLadder, NoiseIsTheSpreadAcrossTheSurface) {
  for (double sigma : {0.01, 0.03}) {
    const PointSpacing s = point_spacing(noisy_gable(sigma, 5));
    EXPECT_NEAR(s.noise, sigma, 0.2 * sigma) << "sigma " << sigma;
  }
  EXPECT_LT(point_spacing(noisy_gable(0, 5)).noise, 0.002) << "a ridge in a few neighbourhoods is no noise";
}

// On a scan at 3 cm of noise 0.1 m apart each face tilts by tens of degrees;
// the roof's two planes are still two planar regions holding nearly every
// face (a mean of the faces' normals split each into several).
TEST(MeshLadder, ANoisyRoofIsItsTwoPlanes) {
  const MeshLadder l = mesh_ladder(noisy_gable(0.03, 6));
  const MeshRegions& r = l.regions;
  std::vector<size_t> faces(r.kinds.size(), 0);
  for (int id : r.face_region) ++faces[size_t(id)];
  std::vector<size_t> planar;
  for (size_t k = 0; k < faces.size(); ++k)
    if (r.kinds[k] == RegionKind::Planar) planar.push_back(faces[k]);
  std::sort(planar.rbegin(), planar.rend());
  ASSERT_GE(planar.size(), 2u);
  EXPECT_GT(double(planar[0] + planar[1]), 0.95 * double(r.face_region.size()));
  EXPECT_LT(double(planar.size() > 2 ? planar[2] : 0), 0.01 * double(r.face_region.size()));
  // Level 3 keeps both whole, within a centimetre, at a tenth of the faces.
  EXPECT_LE(l.level(3).metrics.faces, l.level(4).metrics.faces / 10);
  EXPECT_EQ(l.level(3).change.lost, 0u);
  EXPECT_LE(l.level(3).change.extent_change, 0.01);
}

TEST(MeshLadder, CopiesOfAPlaceCountOnce) {
  std::vector<Vec3> pts = {{0, 0, 0}, {0, 0, 0}, {1, 0, 0}, {1, 0, 0}, {1, 0, 0}};
  const PointSpacing s = point_spacing(pts);
  EXPECT_DOUBLE_EQ(s.min, 1.0);
  EXPECT_DOUBLE_EQ(s.max, 1.0);
}

// The box's floor, where no scan sees: level 1's hull closes on it.
std::vector<Vec3> floor_of_box() {
  std::vector<Vec3> pts;
  for (double x = 0; x <= kWidth + 1e-9; x += kStep)
    for (double y = 0; y <= kDepth + 1e-9; y += kStep) pts.emplace_back(x, y, 0.0);
  return pts;
}

MeshLadder box_ladder(const std::vector<Vec3>& pts, DenseMethod method) {
  return mesh_ladder(pts, method, [](double) { return floor_of_box(); });
}

void expect_ladder(const MeshLadder& l) {
  const MeshMetrics& dense = l.level(4).metrics;
  SCOPED_TRACE(dense_method_name(l.method));
  ASSERT_GT(dense.faces, 1000u);
  EXPECT_LE(dense.mean, kNoise);                          // level 4 follows the points within their noise
  // No face strays past two local spacings (within 5 % of the mean on this even grid).
  EXPECT_LE(dense.mesh_to_cloud, 2.1 * l.spacing.mean);
  EXPECT_LT(dense.far_share, 0.01);                       // and few holes
  EXPECT_LE(l.level(3).metrics.faces, dense.faces / 10);  // level 3 at 10 % of the faces at most
  EXPECT_LE(l.level(2).metrics.faces, l.level(3).metrics.faces);
  // Interpolating methods pass through every point (level 4 deviates by 0):
  // level 3 is held to the noise; Poisson smooths, and is held to its level 4.
  if (l.method == DenseMethod::Poisson) EXPECT_LE(l.level(3).metrics.p95, 1.5 * dense.p95);
  else EXPECT_LE(l.level(3).metrics.p95, 3 * kNoise);
  // Level 3 keeps every planar region, its extent within a centimetre.
  EXPECT_GE(l.level(3).change.regions, 5u);
  EXPECT_EQ(l.level(3).change.lost, 0u);
  EXPECT_LE(l.level(3).change.extent_change, 0.01);
  const MeshMetrics& hull = l.level(1).metrics;
  EXPECT_GT(hull.faces, 12u);
  EXPECT_LE(hull.faces, kLevel1MaxFaces);
  EXPECT_TRUE(hull.closed);
  EXPECT_TRUE(hull.manifold);
  // The box's volume: a hull of the box, not a shell around its walls.
  EXPECT_NEAR(hull.volume, kWidth * kDepth * kHeight, 0.05 * kWidth * kDepth * kHeight);
}

TEST(MeshLadder, AdvancingFrontFollowsTheScannedBox) {
  const std::vector<Vec3> pts = scanned_box(2);
  expect_ladder(box_ladder(pts, DenseMethod::AdvancingFront));
}

TEST(MeshLadder, TheScannedBoxSplitsIntoItsFivePlanes) {
  const MeshLadder l = box_ladder(scanned_box(2), DenseMethod::AdvancingFront);
  const MeshRegions& r = l.regions;
  ASSERT_EQ(r.face_region.size(), l.level(4).mesh.triangles.size());
  EXPECT_EQ(r.count(RegionKind::Planar), 5u) << "the roof and four walls";
  EXPECT_EQ(r.count(RegionKind::Curved), 0u);
  // The planes hold nearly every face; detail is the corners' few.
  std::vector<size_t> faces(r.kinds.size(), 0);
  for (int id : r.face_region) ++faces[size_t(id)];
  size_t planar = 0;
  for (size_t k = 0; k < faces.size(); ++k) planar += r.kinds[k] == RegionKind::Planar ? faces[k] : 0;
  EXPECT_GT(double(planar), 0.97 * double(r.face_region.size()));
  // Level 3 keeps them whole (seed 002's table): no region lost, none's
  // extent moved by more than a centimetre.
  const PlanarChange& c = l.level(3).change;
  EXPECT_EQ(c.regions, 5u);
  EXPECT_EQ(c.lost, 0u);
  EXPECT_LE(c.extent_change, 0.01);
}

TEST(MeshLadder, AVaultIsOneCurvedRegion) {
  std::mt19937 rng(4);
  std::normal_distribution<double> noise(0, kNoise);
  std::vector<Vec3> pts;  // a half cylinder of radius 5 m, 10 m long, a point every kStep
  for (double x = 0; x <= 10 + 1e-9; x += kStep)
    for (double a = 0; a <= M_PI + 1e-9; a += kStep / 5) {
      const double r = 5 + noise(rng);
      pts.emplace_back(x, r * std::cos(a), r * std::sin(a));
    }
  const MeshLadder l = mesh_ladder(pts, DenseMethod::AdvancingFront);
  const MeshRegions& r = l.regions;
  std::vector<size_t> faces(r.kinds.size(), 0);
  for (int id : r.face_region) ++faces[size_t(id)];
  const size_t largest = size_t(std::max_element(faces.begin(), faces.end()) - faces.begin());
  EXPECT_EQ(r.kinds[largest], RegionKind::Curved);
  EXPECT_GT(double(faces[largest]), 0.95 * double(r.face_region.size()));
  EXPECT_EQ(r.count(RegionKind::Planar), 0u);
}

TEST(MeshLadder, BallPivotingFollowsTheScannedBox) {
  const std::vector<Vec3> pts = scanned_box(4);
  expect_ladder(box_ladder(pts, DenseMethod::BallPivoting));
}

// An alpha shape at the points' spacing is their dense surface too, but not
// a 2-manifold (thin slabs, edges of three faces): its repaired soup comes
// apart in sheets whose borders the simplification keeps and whose holes it
// fills, so its lighter levels are level 4 again (the fills outweighed the
// collapse: 33,000 faces from 18,200). The ladder takes an interpolating method.
TEST(MeshLadder, AlphaShapeIsDenseButNotAManifold) {
  const std::vector<Vec3> pts = scanned_box(5);
  const MeshLadder l = box_ladder(pts, DenseMethod::AlphaShape);
  const MeshMetrics& dense = l.level(4).metrics;
  EXPECT_GT(dense.faces, 1000u);
  EXPECT_LE(dense.mean, kNoise);
  EXPECT_LE(dense.mesh_to_cloud, 2 * l.spacing.mean);
  EXPECT_FALSE(dense.manifold);
  EXPECT_LE(l.level(3).metrics.faces, dense.faces);
}

TEST(MeshLadder, PoissonFollowsTheScannedBoxAndIsTrimmed) {
  const std::vector<Vec3> pts = scanned_box(3);
  const MeshLadder l = box_ladder(pts, DenseMethod::Poisson);
  expect_ladder(l);
  EXPECT_GT(l.trimmed, 0u) << "the open floor: Poisson closes it, far from any point";
}

// A flat 40 x 40 grid of squares 0.25 m wide, two triangles each.
TriMesh flat_grid() {
  TriMesh grid;
  const int n = 41;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) grid.vertices.emplace_back(0.25 * i, 0.25 * j, 0.0);
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const int a = j * n + i;
      grid.triangles.push_back({a, a + 1, a + n + 1});
      grid.triangles.push_back({a, a + n + 1, a + n});
    }
  return grid;
}

// The open border stays where it was: its vertices are not moved by the collapse.
TEST(MeshLadder, SimplificationKeepsTheOpenBorder) {
  const TriMesh light = simplified(flat_grid(), 200, 1.0, 0.5, {}).mesh;
  EXPECT_LE(light.triangles.size(), 200u);
  double min_x = 1e9, max_x = -1e9;
  for (const Vec3& v : light.vertices) {
    min_x = std::min(min_x, v.x()), max_x = std::max(max_x, v.x());
    EXPECT_NEAR(v.z(), 0.0, 1e-9);
  }
  EXPECT_DOUBLE_EQ(min_x, 0.0);
  EXPECT_DOUBLE_EQ(max_x, 10.0);
}

// Two regions of one flat grid, split along y = 5 m, the upper one labelled curved.
MeshRegions two_halves(const TriMesh& grid) {
  MeshRegions regions;
  regions.kinds = {RegionKind::Planar, RegionKind::Curved};
  for (const auto& t : grid.triangles) regions.face_region.push_back(grid.vertices[size_t(t[0])].y() < 5 ? 0 : 1);
  return regions;
}

// The vertices where the two halves' faces meet.
std::vector<Vec3> where_halves_meet(const Simplified& s) {
  std::vector<std::array<bool, 2>> in(s.mesh.vertices.size(), {false, false});
  for (size_t f = 0; f < s.mesh.triangles.size(); ++f)
    for (int v : s.mesh.triangles[f]) in[size_t(v)][size_t(s.face_region[f])] = true;
  std::vector<Vec3> out;
  for (size_t v = 0; v < in.size(); ++v)
    if (in[v][0] && in[v][1]) out.push_back(s.mesh.vertices[v]);
  return out;
}

// Stage one keeps the border between the regions whole, and the curved
// region keeps four times the planar one's share of its faces.
TEST(MeshLadder, SimplificationKeepsRegionBordersAndRetention) {
  const TriMesh grid = flat_grid();
  const Simplified light = simplified(grid, 800, 1.0, 0.5, two_halves(grid));
  ASSERT_EQ(light.face_region.size(), light.mesh.triangles.size());
  EXPECT_LE(light.mesh.triangles.size(), 800u);
  EXPECT_EQ(where_halves_meet(light).size(), 41u);
  for (const Vec3& v : where_halves_meet(light)) EXPECT_EQ(v.y(), 5.0);
  const auto planar = std::count(light.face_region.begin(), light.face_region.end(), 0);
  const auto curved = std::count(light.face_region.begin(), light.face_region.end(), 1);
  EXPECT_GT(double(curved), 2.5 * double(planar)) << planar << " planar, " << curved << " curved faces";
}

// Where stage one cannot meet the budget (the planar half's borders alone
// need more faces), stage two thins the border along itself: what is left of
// it stays on the line. Plain edge collapse moves it off.
TEST(MeshLadder, StageTwoThinsABorderAlongItself) {
  const TriMesh grid = flat_grid();
  const Simplified light = simplified(grid, 400, 1.0, 0.5, two_halves(grid));
  EXPECT_LE(light.mesh.triangles.size(), 400u);
  const std::vector<Vec3> border = where_halves_meet(light);
  EXPECT_LT(border.size(), 41u);
  EXPECT_GE(border.size(), 2u);
  for (const Vec3& v : border) EXPECT_EQ(v.y(), 5.0);
  const Simplified plain = simplified(grid, 400, 1.0, 0.5, two_halves(grid), Simplifier::LindstromTurk);
  const std::vector<Vec3> moved = where_halves_meet(plain);
  EXPECT_TRUE(std::any_of(moved.begin(), moved.end(), [](const Vec3& v) { return std::abs(v.y() - 5.0) > 0.1; }));
}

// Points that span no surface: the command refuses them in one line, and an
// alpha shape of exactly flat points (which crashed Open3D's Qhull) is empty.
TEST(MeshLadder, PointsWithoutASurfaceAreRefused) {
  const std::string dir = test::temp_dir("no_surface");
  const auto write = [&](const std::string& name, const std::vector<Vec3>& pts) {
    std::ofstream f(dir + "/" + name);
    for (const Vec3& p : pts) f << p.x() << " " << p.y() << " " << p.z() << "\n";
    return dir + "/" + name;
  };
  std::vector<Vec3> line, flat;
  for (int i = 0; i < 100; ++i) line.emplace_back(0.1 * i, 0, 0), flat.emplace_back(i % 10, i / 10, 0);
  EXPECT_THROW(mesh_point_files({write("line.xyz", line)}, DenseMethod::AdvancingFront, dir, "line"), InputError);
  EXPECT_THROW(mesh_point_files({write("three.xyz", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}})}, DenseMethod::AdvancingFront, dir,
                                "three"),
               InputError);
  EXPECT_TRUE(dense_mesh(flat, point_spacing(flat), DenseMethod::AlphaShape).mesh.triangles.empty());
  EXPECT_GT(dense_mesh(flat, point_spacing(flat), DenseMethod::AdvancingFront).mesh.triangles.size(), 100u);
}

// The ladder's files: PLY and glTF per level, ladder.json; every .glb passes
// the Khronos validator with no error (npm gltf-validator, tests/js).
TEST(MeshLadder, FilesAreWrittenAndTheGltfIsValid) {
  const MeshLadder l = box_ladder(scanned_box(6), DenseMethod::AdvancingFront);
  const std::string dir = test::temp_dir("ladder_files");
  const Vec3 offset(781000, 9240000, 700);
  const std::vector<std::string> files = write_ladder(l, offset, dir, "box");
  ASSERT_EQ(files.size(), 9u);  // 4 PLY, 4 glb, ladder.json
  std::ifstream glb(dir + "/box_level3.glb", std::ios::binary);
  const std::string bytes{std::istreambuf_iterator<char>(glb), {}};
  uint32_t head[5];
  ASSERT_GE(bytes.size(), sizeof head);
  std::memcpy(head, bytes.data(), sizeof head);
  EXPECT_EQ(head[0], 0x46546C67u);  // "glTF"
  EXPECT_EQ(head[1], 2u);
  EXPECT_EQ(head[2], bytes.size());
  EXPECT_EQ(head[4], 0x4E4F534Au);  // the JSON chunk first
  const auto json = nlohmann::json::parse(bytes.substr(20, head[3]));
  EXPECT_EQ(json["accessors"][0]["count"], l.level(3).mesh.vertices.size());
  EXPECT_EQ(json["accessors"][1]["count"], 3 * l.level(3).mesh.triangles.size());
  EXPECT_EQ(json["scenes"][0]["extras"]["world_offset"][1], 9240000.0);
  // The PLY read back (the report's 3D view does): the same triangles, in
  // world coordinates to the float's precision of the local frame.
  const TriMesh& level3 = l.level(3).mesh;
  const TriMesh back = read_local_ply(dir + "/box_level3.ply");
  ASSERT_EQ(back.vertices.size(), level3.vertices.size());
  EXPECT_EQ(back.triangles, level3.triangles);
  for (size_t i = 0; i < back.vertices.size(); ++i)
    EXPECT_LT((back.vertices[i] - offset - level3.vertices[i]).norm(), 1e-5) << i;
  const auto summary = nlohmann::json::parse(std::ifstream(dir + "/box_ladder.json"));
  EXPECT_EQ(summary["levels"][2]["faces"], l.level(3).metrics.faces);
  const std::string js = std::string(C3D_SOURCE_DIR) + "/tests/js";
  C3D_NEED(std::filesystem::exists(js + "/node_modules/gltf-validator/package.json") &&
               test::shell("command -v node").size() > 0,
           "tests/js/node_modules/gltf-validator (scripts/setup.sh) or node missing");
  std::string glbs;
  for (const std::string& f : files)
    if (f.size() > 4 && f.substr(f.size() - 4) == ".glb") glbs += " " + f;
  int rc = -1;
  const std::string out = test::shell("node " + js + "/gltf_check.js" + glbs, &rc);
  EXPECT_EQ(rc, 0) << out;
  size_t clean = 0;
  for (size_t at = out.find(": 0 errors,"); at != std::string::npos; at = out.find(": 0 errors,", at + 1)) ++clean;
  EXPECT_EQ(clean, 4u) << out;  // each level's file read, none with an error
}

}  // namespace
}  // namespace c3d
