// The curved town on more draws than its documented one (docs/curved.md,
// "More draws"): buildings that came out `ok` and wrong, each now within the
// issue's targets (roof, ground and volume 2 %, walls 3 %).
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <string>
#include <utility>
#include <nlohmann/json.hpp>

#include "tests/test_support.h"

using namespace c3d;

// With every wall scanned, every building of the curved town is `ok` within
// the targets (roof, ground and volume 2 %, walls 3 %), at 40 and at
// 10 pts/m2, and the gable is planes only. Two faults this town showed:
// at 40 pts/m2 RANSAC split a vault's points between two near-identical
// cylinders and the roof, held by neither alone, stayed `suspect` with its
// planes; at 10 pts/m2 a gable whose outline cut off a corner left nine
// points beyond its planes, which then fitted worse than a B-spline over the
// rounded ridge: `ok` under a free-form roof, its roof 27 % short.
TEST(CurvedDraws, TownWithEveryWallScannedIsOkWithinTheTargets) {
  for (const std::string density : {"40", "10"}) {
    SCOPED_TRACE(density + " pts/m2");
    const std::string dir = test::temp_dir("primitives_walls_" + density);
    ASSERT_EQ(test::sample_and_batch(dir, "--curved --parcels 24 --seed 11 --occlusion 0 --density " + density,
                                     "--formats cityjson"),
              "");
    const auto truth = nlohmann::json::parse(std::ifstream(dir + "/town/truth.json"));
    const auto summary = nlohmann::json::parse(std::ifstream(dir + "/out/summary.json"));
    ASSERT_EQ(truth["parcels"].size(), summary["parcels"].size());
    for (size_t i = 0; i < truth["parcels"].size(); ++i) {
      const std::string layout = truth["parcels"][i]["layout"], status = summary["parcels"][i]["status"];
      SCOPED_TRACE(layout + " " + std::to_string(i) + ": " + summary["parcels"][i].value("reason", ""));
      EXPECT_EQ(status, "ok");
      ASSERT_EQ(summary["parcels"][i]["buildings"].size(), 1u);
      const auto &model = summary["parcels"][i]["buildings"][0], &exact = truth["parcels"][i]["buildings"][0];
      if (layout == "gable") {
        EXPECT_TRUE(model["mesh_refinement"].is_null()) << "planes only";
        continue;  // the planar model's accuracy is docs/accuracy.md's
      }
      EXPECT_TRUE(model["solid_valid"].get<bool>());
      for (const auto& [figure, target] :
           {std::pair<const char*, double>{"roof_area_m2", 0.02}, {"ground_area_m2", 0.02}, {"wall_area_m2", 0.03},
            {"volume_m3", 0.02}})
        EXPECT_NEAR(model[figure].get<double>() / exact[figure].get<double>(), 1, target) << figure;
    }
  }
}

// Two buildings of the curved town of seed 5 at 10 pts/m2, wall points
// scanned, that came out `ok` and wrong: an onion whose profile fit gave up
// on its steep rim, modelled on a cone (its roof 49 % short, its drum up to
// the cone); a saddle hall whose outline the regulariser ran 2 m past a
// corner its points cut off (its walls 7.6 % long). Each within the targets.
TEST(CurvedDraws, SparseOnionAndSaddleWithinTheTargets) {
  const std::string dir = test::temp_dir("primitives_seed5");
  ASSERT_EQ(test::sample_and_batch(dir, "--curved --parcels 24 --seed 5 --density 10",
                                   "--formats cityjson --where \"NIB IN ('10280503000017', '10280503000019')\""),
            "");
  const auto truth = nlohmann::json::parse(std::ifstream(dir + "/town/truth.json"));
  const auto summary = nlohmann::json::parse(std::ifstream(dir + "/out/summary.json"));
  std::map<std::string, nlohmann::json> exact;
  for (const auto& p : truth["parcels"]) exact[p["parcel_id"]] = p;
  ASSERT_EQ(summary["parcels"].size(), 2u);
  for (const auto& p : summary["parcels"]) {
    const auto& t = exact.at(p["parcel_id"]);
    SCOPED_TRACE(t["layout"].get<std::string>() + ": " + p.value("reason", ""));
    EXPECT_EQ(p["status"], "ok");
    ASSERT_EQ(p["buildings"].size(), 1u);
    for (const auto& [figure, target] :
         {std::pair<const char*, double>{"roof_area_m2", 0.02}, {"ground_area_m2", 0.02}, {"wall_area_m2", 0.03},
          {"volume_m3", 0.02}})
      EXPECT_NEAR(p["buildings"][0][figure].get<double>() / t["buildings"][0][figure].get<double>(), 1, target)
          << figure;
  }
}
