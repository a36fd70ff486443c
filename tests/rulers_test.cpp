// The batch-wide rulers (core/evaluate/ruler.h): figures with known answers,
// and on Cimahi figure for figure what the shared judge
// (tools/eval_cityjson.py) reads from the batch's CityJSON.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "core/evaluate/ruler.h"
#include "tests/test_support.h"

using namespace c3d;
namespace fs = std::filesystem;
using nlohmann::json;

TEST(Rulers, FiguresOfKnownDistances) {
  // 0.05, 0.15, ..., 0.95 m and one point with no surface at all (a 99 m miss).
  std::vector<double> d;
  for (int i = 0; i < 10; ++i) d.push_back(0.05 + 0.1 * i);
  d.push_back(kNaN);
  const RulerFigures r = ruler_figures(d);
  EXPECT_EQ(r.n, 11);
  EXPECT_NEAR(r.median, 0.55, 1e-12);
  EXPECT_NEAR(r.nmad, 1.4826 * 0.3, 1e-12);  // |d - 0.55|: 0 0.1 0.1 0.2 0.2 0.3 0.3 0.4 0.4 0.5 98.45
  EXPECT_NEAR(r.share_over_0_3m, 8.0 / 11, 1e-12);
  EXPECT_NEAR(r.share_over_1m, 1.0 / 11, 1e-12);
  EXPECT_NEAR(r.rmse_within_1m, std::sqrt(3.325 / 10), 1e-12);  // 0.0025 x (1 + 9 + 25 + ... + 361)
  EXPECT_NEAR(r.max, 99.0, 1e-12);
  EXPECT_NEAR(r.p95, 0.95 + 0.5 * (99.0 - 0.95), 1e-9);  // halfway between the 10th and 11th of 11
}

TEST(Rulers, WallPointsNearAFootprintEdge) {
  const std::vector<Ring3> footprint = {{{0, 0, 0}, {10, 0, 0}, {10, 8, 0}, {0, 8, 0}}};
  const std::vector<Vec3> pts = {{5, -1.4, 3}, {5, -1.6, 3}, {11.0, 9.0, 2}, {12, 9, 2}, {5, 4, 1}};
  // 1.4 m and 1.6 m south; 1.41 m from the corner; 2.2 m; 4 m inside (no edge within 1.5 m).
  EXPECT_EQ(near_rings(pts, footprint, kFootprintReachM), (std::vector<char>{1, 0, 1, 0, 0}));
}

TEST(Rulers, CimahiFiguresAreTheSharedJudges) {
  C3D_REQUIRE_CIMAHI();
  const fs::path judge = fs::path(test::cimahi_dir()).parent_path().parent_path() / "tools" / "eval_cityjson.py";
  C3D_NEED(fs::exists(judge), judge << " not found");
  C3D_NEED(std::system("/usr/bin/python3 -c 'import numpy, osgeo' 2>/dev/null") == 0, "python3-numpy/gdal missing");
  const std::string c = test::cimahi_dir(), out = test::temp_dir("cimahi");
  std::string log;
  ASSERT_EQ(test::run_cli("batch --quiet --cloud " + c + "/cimahi.las --parcels " + c + "/parcels.shp --dtm " + c +
                          "/dtm.tif --out " + out + " --formats cityjson", &log), 0) << log;
  const std::string cmd = "/usr/bin/python3 " + judge.string() + " " + out + "/buildings.city.json " + c +
                          "/parcels.shp " + c + "/roof.ply " + c + "/walls.ply > " + out + "/judge.json 2>/dev/null";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  std::ifstream jf(out + "/judge.json"), sf(out + "/summary.json");
  const json judge_out = json::parse(jf), summary = json::parse(sf);
  for (const char* part : {"roof", "wall"}) {
    const json& ours = summary[std::string(part) + "_ruler"];
    const json& theirs = judge_out[part];
    EXPECT_EQ(ours["n"], theirs["n"]) << part;
    for (const char* k : {"median", "nmad", "p95", "rmse_within_1m"})
      EXPECT_NEAR(ours[k].get<double>(), theirs[k].get<double>(), 1e-3) << part << " " << k;
    for (const char* k : {"share_over_0_3m", "share_over_1m"})
      EXPECT_NEAR(ours[k].get<double>(), theirs[k].get<double>(), 1e-3) << part << " " << k;
  }
  EXPECT_NEAR(summary["wall_points_measured_share"].get<double>(),
              judge_out["wall"]["share_of_wall_points_measured"].get<double>(), 1e-3);
}
