// The sample town's cloud as LAZ tiles (`cadastre3d sample --laz --tiles`):
// the same points as the one LAS file, each in its own tile, and the batch
// reading the tiles as a list of --cloud files models the town as from the LAS.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/io/point_io.h"
#include "core/synthetic/sample_town.h"
#include "tests/test_support.h"

namespace c3d {
namespace {

std::vector<std::array<double, 4>> sorted_points(const PointCloud& c) {
  std::vector<std::array<double, 4>> v;
  for (size_t i = 0; i < c.points.size(); ++i)
    v.push_back({c.points[i].x(), c.points[i].y(), c.points[i].z(), double(c.classes[i])});
  std::sort(v.begin(), v.end());
  return v;
}

TEST(SampleTiles, TilesHoldTheCloudsPointsEachInItsSquare) {
  SampleOptions opt;
  opt.parcels = 24;
  opt.seed = 3;
  const SampleTown town = make_sample_town(opt);
  const std::string dir = test::temp_dir("tiles");
  const double size = 40;
  const std::vector<std::string> tiles = write_cloud_tiles(town.cloud, dir + "/cloud", {true, size});
  ASSERT_GT(tiles.size(), 4u);
  write_las(dir + "/cloud.las", town.cloud, 6, 4);
  PointCloud all;
  for (const std::string& path : tiles) {
    ASSERT_EQ(std::filesystem::path(path).extension(), ".laz");
    const PointCloud tile = read_point_cloud(path);
    ASSERT_FALSE(tile.points.empty()) << path;
    EXPECT_EQ(tile.crs_wkt, read_point_cloud(dir + "/cloud.las").crs_wkt);
    // E<x>_N<y>: the south-west corner; every point within the square (1 mm rounding).
    double e = 0, n = 0;
    ASSERT_EQ(std::sscanf(std::filesystem::path(path).filename().c_str(), "E%lf_N%lf", &e, &n), 2) << path;
    for (const Vec3& p : tile.points) {
      ASSERT_GE(p.x(), e - 0.001) << path;
      ASSERT_LE(p.x(), e + size + 0.001) << path;
      ASSERT_GE(p.y(), n - 0.001) << path;
      ASSERT_LE(p.y(), n + size + 0.001) << path;
    }
    all.points.insert(all.points.end(), tile.points.begin(), tile.points.end());
    all.classes.insert(all.classes.end(), tile.classes.begin(), tile.classes.end());
  }
  const PointCloud las = read_point_cloud(dir + "/cloud.las");
  ASSERT_EQ(all.points.size(), las.points.size());
  // Each tile has its own header offset: coordinates agree to the 1 mm of the records.
  const auto a = sorted_points(all), b = sorted_points(las);
  for (size_t i = 0; i < a.size(); ++i)
    for (int k = 0; k < 4; ++k) ASSERT_NEAR(a[i][k], b[i][k], 0.0011) << "point " << i;
}

TEST(SampleTiles, BadTileSizeIsRefused) {
  PointCloud cloud;
  for (int i = 0; i <= 100000; ++i) cloud.points.push_back(Vec3(i, 0, 0));
  const std::string dir = test::temp_dir("bad");
  EXPECT_THROW(write_cloud_tiles(cloud, dir + "/tiles", {true, 0}), std::exception);
  EXPECT_THROW(write_cloud_tiles(cloud, dir + "/tiles", {true, 0.5}), std::exception);  // a tile a point
  EXPECT_FALSE(std::filesystem::exists(dir + "/tiles")) << "nothing written before the tiles are known";
}

// The batch on the tiles as a list of --cloud files, against the batch on the LAS.
TEST(SampleTiles, BatchOnTilesModelsTheTownAsOnTheLas) {
  const std::string dir = test::temp_dir("batch");
  std::string out;
  ASSERT_EQ(test::run_cli("sample --out " + dir + "/las --parcels 20 --seed 5", &out), 0) << out;
  ASSERT_EQ(test::run_cli("sample --out " + dir + "/laz --parcels 20 --seed 5 --laz --tiles 60", &out), 0) << out;
  std::string tiles;
  for (const auto& e : std::filesystem::directory_iterator(dir + "/laz/cloud")) tiles += " " + e.path().string();
  const std::string common = " --parcels " + dir + "/las/parcels.gpkg --dtm " + dir + "/las/dtm.tif --formats obj --quiet";
  int rc = test::run_cli("batch --cloud " + dir + "/las/cloud.las --out " + dir + "/out_las" + common, &out);
  ASSERT_TRUE(rc == 0 || rc == 3) << out;
  rc = test::run_cli("batch --cloud" + tiles + " --out " + dir + "/out_laz" + common, &out);
  ASSERT_TRUE(rc == 0 || rc == 3) << out;
  const auto las = nlohmann::json::parse(std::ifstream(dir + "/out_las/summary.json"))["parcels"];
  const auto laz = nlohmann::json::parse(std::ifstream(dir + "/out_laz/summary.json"))["parcels"];
  ASSERT_EQ(las.size(), laz.size());
  for (size_t i = 0; i < las.size(); ++i) {
    EXPECT_EQ(las[i]["status"], laz[i]["status"]) << las[i]["parcel_id"];
    EXPECT_EQ(las[i].value("buildings", nlohmann::json::array()).size(),
              laz[i].value("buildings", nlohmann::json::array()).size());
  }
  EXPECT_EQ(las, laz) << "the same parcels, elements and areas";
}

}  // namespace
}  // namespace c3d
