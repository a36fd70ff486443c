// Round and apsed roofs end on their circles (outline/arcs.h); straight-edged
// ones, an octagon among them, keep their polygons; in the batch the wall
// under an arc is one wall.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <random>

#include "core/geometry/geometry.h"
#include "core/reconstruct/outline/outline.h"
#include "tests/test_support.h"

using namespace c3d;

namespace {

// Roof points spread evenly over a plan region (as from the air) at
// `density` per m2, with 3 cm of planimetric noise.
std::vector<Vec2> scan(const std::function<bool(const Vec2&)>& inside, double x0, double x1, double y0, double y1,
                       double density, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> ux(x0, x1), uy(y0, y1);
  std::normal_distribution<double> noise(0, 0.03);
  std::vector<Vec2> out;
  const int n = int(density * (x1 - x0) * (y1 - y0));
  for (int i = 0; i < n; ++i) {
    const Vec2 q(ux(rng), uy(rng));
    if (inside(q)) out.push_back(q + Vec2(noise(rng), noise(rng)));
  }
  return out;
}

// An outline with more vertices than this has a circle's chords in it (a
// circle of radius 5 in 2 cm chords has 36).
constexpr size_t kNoChords = 12;

bool in_octagon(const Vec2& q, double r) {  // a regular octagon of circumradius r, flat sides on the axes
  const double apothem = r * std::cos(M_PI / 8);
  return std::abs(q.x()) <= apothem && std::abs(q.y()) <= apothem && std::abs(q.x()) + std::abs(q.y()) <= apothem * std::sqrt(2);
}

}  // namespace

// A round tower of radius 6 and a hall of 16 x 10 m with a half-circle apse
// of radius 5, three scans each at 10 and 40 points per m2: before, their
// outlines were polygons of 8-12 edges, the round roof 2-3 % off (up to 10
// of its sigma). Now every tower ends on its circle, within 0.8 %, and the
// apses within 1.5 %.
TEST(OutlineArcs, RoundAndApsedRoofsEndOnTheirCircles) {
  int circles = 0;
  for (double density : {10.0, 40.0})
    for (unsigned seed : {1u, 2u, 3u}) {
      OutlineOptions opt;
      opt.spacing = 0.5 / std::sqrt(density);  // the nearest-neighbour distance, as the batch reads it
      const auto round = scan([](const Vec2& q) { return q.norm() < 6; }, -8, 8, -8, 8, density, seed);
      const Polygon2 o = roof_outline(round, opt);
      EXPECT_NEAR(area(o) / (M_PI * 36), 1, 0.01) << density << " pts/m2, seed " << seed;
      circles += o.outer.size() > kNoChords;

      const auto apsed = scan(
          [](const Vec2& q) {
            return (q.x() >= 0 && q.x() <= 16 && q.y() >= 0 && q.y() <= 10) || (q - Vec2(16, 5)).norm() < 5;
          },
          -2, 23, -2, 12, density, seed);
      const Polygon2 a = roof_outline(apsed, opt);
      EXPECT_NEAR(area(a) / (160 + M_PI * 25 / 2), 1, 0.02) << density << " pts/m2, seed " << seed;
    }
  EXPECT_EQ(circles, 6);
}

// Straight edges stay straight: a rectangle gets no arc, nor does an octagon
// (whose corners a circle of its area passes within 0.3 m of) at 40 points
// per m2. At 10 points per m2 an octagon is taken for its circle in 3 scans
// of 20 (docs/curved.md).
TEST(OutlineArcs, StraightEdgedRoofsKeepTheirPolygons) {
  for (double density : {10.0, 40.0}) {
    OutlineOptions opt;
    opt.spacing = 0.5 / std::sqrt(density);
    const auto rect = scan([](const Vec2& q) { return q.x() >= 0 && q.x() <= 14 && q.y() >= 0 && q.y() <= 9; },
                           -2, 16, -2, 11, density, 4);
    const Polygon2 r = roof_outline(rect, opt);
    EXPECT_LE(r.outer.size(), kNoChords) << density;
    EXPECT_NEAR(area(r) / 126, 1, 0.02) << density;
  }
  OutlineOptions opt;
  opt.spacing = 0.5 / std::sqrt(40.0);
  for (unsigned seed : {5u, 6u, 7u}) {
    const auto oct = scan([](const Vec2& q) { return in_octagon(q, 6); }, -7, 7, -7, 7, 40, seed);
    const Polygon2 o = roof_outline(oct, opt);
    EXPECT_LE(o.outer.size(), kNoChords) << "seed " << seed;
    EXPECT_NEAR(area(o) / (2 * std::sqrt(2) * 36), 1, 0.02) << "seed " << seed;
  }
}

// The batch on a town of round towers and apsed halls (`sample
// --curved-plans`, 40 pts/m2, walls scanned): every one `ok`, planes only,
// valid, its roof within the 2 %; a tower's drum one wall element,
// an apse one beside the hall's straight walls (not one per chord).
TEST(OutlineArcs, BatchEndsFlatRoofsOnTheirCircles) {
  const std::string dir = test::temp_dir("outline_arcs_batch");
  ASSERT_EQ(test::sample_and_batch(dir, "--curved-plans --parcels 12 --seed 11"), "");
  const auto truth = nlohmann::json::parse(std::ifstream(dir + "/town/truth.json"));
  const auto summary = nlohmann::json::parse(std::ifstream(dir + "/out/summary.json"));
  ASSERT_EQ(truth["parcels"].size(), summary["parcels"].size());
  int curved = 0;
  for (size_t i = 0; i < truth["parcels"].size(); ++i) {
    const std::string layout = truth["parcels"][i]["layout"];
    if (layout != "round_tower" && layout != "apsed_hall") continue;
    ++curved;
    const auto& parcel = summary["parcels"][i];
    EXPECT_EQ(parcel["status"], "ok") << layout << ": " << parcel.value("reason", "");
    ASSERT_EQ(parcel["buildings"].size(), 1u) << layout;
    const auto &m = parcel["buildings"][0], &t = truth["parcels"][i]["buildings"][0];
    EXPECT_TRUE(m["mesh_refinement"].is_null()) << layout << ": planes only";
    EXPECT_TRUE(m["solid_valid"].get<bool>()) << layout;
    EXPECT_NEAR(m["roof_area_m2"].get<double>() / t["roof_area_m2"].get<double>(), 1, 0.02) << layout;
    const double walls = test::sql_number(
        dir + "/out/cadastre.gpkg", "select count(*) from building_element e join building b on e.building_fid = b.fid "
                                    "where e.element_type = 'wall' and b.building_id = '" +
                                        m["building_id"].get<std::string>() + "'");
    if (layout == "round_tower") EXPECT_EQ(walls, 1) << m["building_id"];
    else EXPECT_LE(walls, 6) << m["building_id"];
  }
  EXPECT_EQ(curved, 8);
}

// A town is either curved or of curved plans: asked for both, `sample` says
// so and does nothing (a usage error).
TEST(OutlineArcs, CurvedAndCurvedPlansTownsExcludeEachOther) {
  std::string out;
  const std::string dir = test::temp_dir("outline_arcs_exclusive");
  EXPECT_EQ(test::run_cli("sample --curved --curved-plans --out " + dir + "/town", &out), 2) << out;
  EXPECT_NE(out.find("--curved excludes --curved-plans"), std::string::npos) << out;
  EXPECT_FALSE(std::ifstream(dir + "/town/truth.json").good());
}
