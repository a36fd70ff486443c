// The simple morphological ground filter (core/classify/ground_filter.h,
// issue 51) on a scene with known ground, and on IGN's labelled tiles
// (../shared/data/labelled), whose ground class is IGN's.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <random>

#include "core/classify/ground_filter.h"
#include "core/io/point_io.h"
#include "tests/test_support.h"

namespace c3d {
namespace {

struct Scored {
  double precision = 0, recall = 0;
};

Scored scored(const std::vector<char>& found, const std::vector<char>& truth) {
  long tp = 0, fp = 0, fn = 0;
  for (size_t k = 0; k < found.size(); ++k) {
    tp += found[k] && truth[k];
    fp += found[k] && !truth[k];
    fn += !found[k] && truth[k];
  }
  return {tp + fp ? double(tp) / double(tp + fp) : 0, tp + fn ? double(tp) / double(tp + fn) : 0};
}

// 80 x 80 m of terrain rising 5 % to the east, a point every 0.3 m; a 20 x 12 m
// flat-roofed building 7 m high with its walls; a 6 m tree crown on a trunk.
// Far from any origin, as national grids are.
TEST(GroundFilter, FindsTheTerrainUnderABuildingAndATree) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0, 0.02);
  std::uniform_real_distribution<double> u(0, 1);
  const Vec3 origin(770000, 6277000, 100);
  std::vector<Vec3> pts;
  std::vector<char> truth;
  const auto ground_z = [](double x) { return 0.05 * x; };
  const auto add = [&](double x, double y, double z, bool ground) {
    pts.push_back(origin + Vec3(x, y, z + noise(rng)));
    truth.push_back(ground);
  };
  const auto in_building = [](double x, double y) { return x > 30 && x < 50 && y > 30 && y < 42; };
  for (double x = 0; x < 80; x += 0.3)
    for (double y = 0; y < 80; y += 0.3)
      if (!in_building(x, y)) add(x, y, ground_z(x), true);
  for (double x = 30; x <= 50; x += 0.3)
    for (double y = 30; y <= 42; y += 0.3) add(x, y, ground_z(40) + 7, false);
  for (double z = 0.5; z < 7; z += 0.3)
    for (double t = 0; t <= 20; t += 0.3) add(30 + t, 30, ground_z(30 + t) + z, false);
  for (int k = 0; k < 3000; ++k) {  // a crown 3-9 m up, 6 m across, at (15, 60)
    const double a = 2 * M_PI * u(rng), r = 3 * std::sqrt(u(rng)), h = 3 + 6 * u(rng);
    add(15 + r * std::cos(a), 60 + r * std::sin(a), ground_z(15) + h, false);
  }
  const GroundFilter g = smrf_ground(pts);
  const Scored s = scored(g.ground, truth);
  EXPECT_GT(s.precision, 0.995);
  EXPECT_GT(s.recall, 0.99);
  EXPECT_GT(g.objects, 200) << "the building's 240 cells and the crown's";
  // The terrain runs under the building as around it.
  EXPECT_NEAR(g.terrain.height_at(origin.x() + 40, origin.y() + 36), origin.z() + ground_z(40), 0.3);
}

TEST(GroundFilter, NoPointsNoGround) {
  const GroundFilter g = smrf_ground({});
  EXPECT_TRUE(g.ground.empty());
  EXPECT_EQ(g.terrain.nx, 0);
}

// IGN's five adjacent tiles, filtered together (one town, 100 x 100 m), each
// scored against its ground class (2), beside PCL's approximate progressive
// morphological filter. Prints the table docs/classification.md holds.
TEST(GroundFilter, IgnLabelledTiles) {
  const std::filesystem::path dir = std::filesystem::path(C3D_SOURCE_DIR) / "../shared/data/labelled";
  C3D_NEED(std::filesystem::exists(dir), "../shared/data/labelled missing");
  std::vector<std::string> tiles;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == ".laz") tiles.push_back(e.path().string());
  std::sort(tiles.begin(), tiles.end());
  std::vector<Vec3> all;
  std::vector<char> truth;
  std::vector<size_t> ends;
  for (const std::string& t : tiles) {
    const PointCloud c = read_point_cloud(t);
    ASSERT_EQ(c.classes.size(), c.points.size()) << t;
    all.insert(all.end(), c.points.begin(), c.points.end());
    for (auto code : c.classes) truth.push_back(code == 2);
    ends.push_back(all.size());
  }
  const GroundFilter g = smrf_ground(all);
  const std::vector<char> pmf = pcl_pmf_ground(all);
  size_t begin = 0;
  for (size_t k = 0; k < tiles.size(); ++k) {
    const std::vector<char> found(g.ground.begin() + long(begin), g.ground.begin() + long(ends[k]));
    const std::vector<char> known(truth.begin() + long(begin), truth.begin() + long(ends[k]));
    const Scored s = scored(found, known);
    const std::vector<char> by_pcl(pmf.begin() + long(begin), pmf.begin() + long(ends[k]));
    const Scored t = scored(by_pcl, known);
    std::printf("%s: ground precision / recall %.3f / %.3f (PCL's approximate PMF: %.3f / %.3f)\n",
                std::filesystem::path(tiles[k]).filename().c_str(), s.precision, s.recall, t.precision, t.recall);
    EXPECT_GT(s.precision, 0.9) << tiles[k];
    EXPECT_GT(s.recall, 0.95) << tiles[k];
    begin = ends[k];
  }
}

}  // namespace
}  // namespace c3d
