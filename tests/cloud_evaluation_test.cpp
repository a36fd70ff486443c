// classify --cloud FILE --evaluate (issue 51): a labelled survey judged as if
// it came unclassified, scored per survey class; on IGN's labelled tiles,
// whose class counts ../shared/data/labelled/README.md gives.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "cadastre/classify/cloud_evaluation.h"
#include "core/io/point_io.h"
#include "tests/test_support.h"

namespace c3d {
namespace {

TEST(CloudEvaluation, BuildingCountsRoofAndWallVegetationOther) {
  CloudEvaluation e;
  auto& c = e.confusion;
  c[size_t(SurveyClass::Ground)] = {90, 5, 0, 5};     // called ground, roof, wall, other
  c[size_t(SurveyClass::Building)] = {2, 30, 8, 0};
  c[size_t(SurveyClass::Vegetation)] = {8, 10, 2, 40};
  EXPECT_DOUBLE_EQ(e.recall(SurveyClass::Ground), 0.9);
  EXPECT_DOUBLE_EQ(e.precision(SurveyClass::Ground), 0.9);          // 90 of 100 called ground
  EXPECT_DOUBLE_EQ(e.recall(SurveyClass::Building), 38.0 / 40);     // roof and wall both count
  EXPECT_DOUBLE_EQ(e.precision(SurveyClass::Building), 38.0 / 55);
  EXPECT_DOUBLE_EQ(e.recall(SurveyClass::Vegetation), 40.0 / 60);
  EXPECT_DOUBLE_EQ(e.precision(SurveyClass::Vegetation), 40.0 / 45);
  EXPECT_DOUBLE_EQ(e.accuracy(), (90 + 38 + 40) / 200.0);
  EXPECT_EQ(e.support(SurveyClass::Building), 40);
  EXPECT_TRUE(std::isnan(CloudEvaluation{}.precision(SurveyClass::Ground)));
}

// With the ground filter's terrain flat ground is ground again (the lowest
// points of 10 m cells had left 46 % of it at roof height: recall 0.54).
TEST(CloudEvaluation, IgnTileGroundIsFoundWithoutItsClass) {
  const std::filesystem::path tile =
      std::filesystem::path(C3D_SOURCE_DIR) / "../shared/data/labelled/ign_lidarhd_77050_627760.laz";
  C3D_NEED(std::filesystem::exists(tile), "../shared/data/labelled missing");
  const PointForest forest = PointForest::load(std::string(C3D_SOURCE_DIR) + "/models/classifier.yml.gz");
  const CloudEvaluation e = evaluate_cloud(forest, read_point_cloud(tile.string()), ClassMapping{});
  EXPECT_GT(e.recall(SurveyClass::Ground), 0.95);
  EXPECT_GT(e.precision(SurveyClass::Ground), 0.95);
  EXPECT_GT(e.accuracy(), 0.8);
}

TEST(CloudEvaluation, IgnTileThroughTheCli) {
  const std::filesystem::path tile =
      std::filesystem::path(C3D_SOURCE_DIR) / "../shared/data/labelled/ign_lidarhd_77050_627760.laz";
  C3D_NEED(std::filesystem::exists(tile), "../shared/data/labelled missing");
  const std::string dir = test::temp_dir("cloud_evaluation");
  std::string out;
  ASSERT_EQ(test::run_cli("classify --cloud " + tile.string() + " --evaluate --table " + dir + "/t.md", &out), 0) << out;
  // The README's counts: ground (2) 33,568, vegetation (3-5) 13,466; building 6 (4,148) and IGN's 64 here.
  EXPECT_NE(out.find("| ground | 33568 |"), std::string::npos) << out;
  EXPECT_NE(out.find("| vegetation | 13466 |"), std::string::npos) << out;
  EXPECT_NE(out.find("accuracy 0."), std::string::npos) << out;
  EXPECT_NE(out.find("no ground-class points"), std::string::npos) << "the terrain found without the file's ground class";
  EXPECT_TRUE(std::filesystem::exists(dir + "/t.md"));
  std::printf("%s", out.c_str());
  // A cloud without classes has nothing to be judged against: one line naming it.
  std::ofstream(dir + "/bare.xyz") << "0 0 0\n1 0 0\n0 1 0\n1 1 0.5\n";
  EXPECT_EQ(test::run_cli("classify --cloud " + dir + "/bare.xyz --evaluate", &out), 1) << out;
  EXPECT_NE(out.find("bare.xyz"), std::string::npos) << out;
  EXPECT_NE(out.find("has no classes"), std::string::npos) << out;
}

}  // namespace
}  // namespace c3d
