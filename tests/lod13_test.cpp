// LoD 1.3: height layers of a two-level building (known heights and areas),
// a noisy rectangle regularised into a rectangle within its IoU level, the
// stacked solid of a stepped building valid by our check and by val3dity
// (where ../shared has it), and a building whose LoD 2.2 is invalid taking
// its layers with a note. (The AHN3 town end to end, where the fallback picks
// LoD 1.3 before the prism, is in lod12_test.)
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <random>

#include "core/check/solid_check.h"
#include "core/geometry/geometry.h"
#include "core/geometry/polygon_ops.h"
#include "core/reconstruct/lod13/layer_solid.h"
#include "core/reconstruct/lod13/layers.h"
#include "core/reconstruct/lod13/lod13.h"
#include "core/reconstruct/lod13/regularise.h"
#include "core/reconstruct/measure/measure.h"
#include "tests/test_support.h"

using namespace c3d;
namespace fs = std::filesystem;

namespace {

// A 20 x 10 m block on flat terrain at z = 1: roof points every 0.3 m with
// 3 cm noise, at 5 m where x < 12 and at 11 m over the 8 x 10 m tower beyond.
PrismInput two_level(std::vector<Vec3>& points) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0, 0.03);
  points.clear();
  for (double x = 0.15; x < 20; x += 0.3)
    for (double y = 0.15; y < 10; y += 0.3) points.emplace_back(x, y, (x < 12 ? 5.0 : 11.0) + noise(rng));
  PrismInput in;
  in.building_id = "T_b1";
  in.footprint = {{{0, 0}, {20, 0}, {20, 10}, {0, 10}}, {}};
  for (const auto& p : points) in.roof_heights.push_back(p.z());
  in.terrain = [](double, double) { return 1.0; };
  in.spacing = 0.3;
  return in;
}

double polygon_iou(const Polygon2& a, const Polygon2& b) {
  const double both = area(poly::intersect({a}, {b})), either = area(poly::unite({a}, {b}));
  return either > 0 ? both / either : 0;
}

}  // namespace

TEST(Lod13, TwoLevelBuildingGivesTwoLayersWithTheirAreas) {
  std::vector<Vec3> points;
  const PrismInput in = two_level(points);
  const lod13::HeightGrid g = lod13::height_grid(in.footprint, points, 0.5);
  const std::vector<lod13::Layer> layers = lod13::layer_tree(g, lod13::LayerOptions{});
  ASSERT_EQ(layers.size(), 2u);
  EXPECT_EQ(layers[1].parent, 0);
  EXPECT_NEAR(layers[0].z, 5.0, 0.1);
  EXPECT_NEAR(layers[1].z, 11.0, 0.1);
  EXPECT_NEAR(double(layers[0].cells.size()) * 0.25, 200.0, 1e-9);  // the footprint
  EXPECT_NEAR(double(layers[1].cells.size()) * 0.25, 80.0, 2.0);    // the tower, to a cell row
}

TEST(Lod13, TwoLevelBuildingIsAValidStackOfPrisms) {
  std::vector<Vec3> points;
  const PrismInput in = two_level(points);
  Lod13Summary sum;
  const Building b = lod13_layers(in, points, {}, &sum);
  ASSERT_TRUE(b.solid_valid) << b.solid_problem;
  EXPECT_EQ(b.lod, Lod::Lod13);
  EXPECT_EQ(b.lod_note, "LoD 1.3 of 2 height layers");
  ASSERT_EQ(sum.layers, 2);
  EXPECT_NEAR(sum.heights[0], 4.0, 0.1);
  EXPECT_NEAR(sum.heights[1], 10.0, 0.1);
  ASSERT_EQ(sum.iou.size(), 1u);
  EXPECT_GE(sum.iou[0], 0.95);
  // The tower's walls lie within a spacing of x = 12: areas and volume to that.
  EXPECT_NEAR(totals(b).roof, 200.0, 1e-6);  // flat parts: plan = footprint
  EXPECT_NEAR(totals(b).ground, 200.0, 1e-6);
  EXPECT_NEAR(b.volume, 120 * 4.0 + 80 * 10.0, 30.0);
  EXPECT_NEAR(totals(b).wall, 34 * 4.0 + 26 * 10.0 + 10 * 6.0, 5.0);  // outer walls + the step
  int steps = 0;
  for (const auto& e : b.elements) steps += e.evidence == WallEvidence::RoofStep;
  EXPECT_GE(steps, 1);
}

TEST(Lod13, NoisyRectangleIsRegularisedIntoARectangle) {
  const double turn = 20 * M_PI / 180;
  const Vec2 u(std::cos(turn), std::sin(turn)), v(-u.y(), u.x());
  const Polygon2 truth{{Vec2::Zero(), 12 * u, 12 * u + 7 * v, 7 * v}, {}};
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> jitter(-0.12, 0.12);
  Ring2 noisy;  // three vertices per side, each off by up to 12 cm
  for (size_t i = 0; i < 4; ++i)
    for (double t : {0.0, 0.35, 0.7}) {
      const Vec2 p = truth.outer[i] + t * (truth.outer[(i + 1) % 4] - truth.outer[i]);
      noisy.push_back(p + Vec2(jitter(rng), jitter(rng)));
    }
  lod13::RegulariseInput in;
  in.outline = {noisy, {}};
  in.iou = [&](const Polygon2& p) { return polygon_iou(p, truth); };
  in.axis = turn + 0.02;  // the building's axis, as found, a degree off
  const lod13::Regularised r = lod13::regularise(in);
  ASSERT_EQ(r.outline.outer.size(), 4u) << r.steps.size() << " steps kept";
  for (size_t i = 0; i < 4; ++i) {
    const Vec2 a = r.outline.outer[i], b = r.outline.outer[(i + 1) % 4], c = r.outline.outer[(i + 2) % 4];
    EXPECT_NEAR((b - a).normalized().dot((c - b).normalized()), 0.0, 1e-9) << "corner " << i;
  }
  std::cout << "noisy rectangle: IoU " << r.iou_found << " as found, " << r.iou << " regular\n";
  EXPECT_GE(r.iou, r.iou_found - lod13::kMaxIouLoss);
  EXPECT_GE(r.iou, 0.97);
  EXPECT_FALSE(r.steps.empty());
  EXPECT_EQ(r.steps.front(), "parallel walls");
}

TEST(Lod13, RegularisationStopsAtTheIouLevel) {
  // An L whose short arm is real: squaring it away would cost far more than
  // the level allows, so the outline keeps six corners.
  const Polygon2 ell{{{0, 0}, {10, 0}, {10, 4}, {4, 4}, {4, 8}, {0, 8}}, {}};
  lod13::RegulariseInput in;
  in.outline = ell;
  in.iou = [&](const Polygon2& p) { return polygon_iou(p, ell); };
  in.min_edge_m = 5;  // would remove the 4 m jogs if the IoU allowed
  const lod13::Regularised r = lod13::regularise(in);
  EXPECT_EQ(r.outline.outer.size(), 6u);
  EXPECT_NEAR(r.iou, 1.0, 1e-9);
  const Polygon2 squared{{{0, 0}, {10, 0}, {10, 8}, {0, 8}}, {}};
  EXPECT_LT(polygon_iou(squared, ell), 1.0 - lod13::kMaxIouLoss);  // 0.7: what squaring it would cost
}

namespace {

// A stepped building: a 20 x 12 m base at 4 m, a 10 x 8 m block at 9 m flush
// with its east wall, a 4 x 4 m tower at 14 m on that block, and a 3 x 3 m
// annex at 6 m standing on the base alone.
std::vector<lod13::LayerPiece> stepped() {
  return {{{{{0, 0}, {20, 0}, {20, 12}, {0, 12}}, {}}, 4.0},
          {{{{10, 2}, {20, 2}, {20, 10}, {10, 10}}, {}}, 9.0},
          {{{{14, 4}, {18, 4}, {18, 8}, {14, 8}}, {}}, 14.0},
          {{{{2, 2}, {5, 2}, {5, 5}, {2, 5}}, {}}, 6.0}};
}

}  // namespace

TEST(Lod13, SteppedSolidIsValidByOurCheckAndVal3dity) {
  const lod13::StackedSolid s = lod13::stacked_solid(stepped(), 0.0, {false, true, false, false});
  ASSERT_EQ(s.problem, "");
  const std::vector<Face> shell = lod13::shell_of(s);
  const SolidCheck check = check_solid(shell);
  ASSERT_TRUE(check.ok) << check.summary();
  EXPECT_NEAR(closed_volume(shell), 240 * 4.0 + 80 * 5.0 + 16 * 5.0 + 9 * 2.0, 1e-6);
  EXPECT_EQ(s.roofs.size(), 4u);  // the base's top holed / notched by the block and the annex
  int party = 0, step = 0;
  double party_area = 0;
  for (const auto& w : s.walls) {
    party += w.party;
    step += !w.outer;
    if (w.party) party_area += area(w.face);
  }
  EXPECT_EQ(step, 4 + 4 + 3);  // the block on the base (3 sides), the tower, the annex (4 each)
  EXPECT_EQ(party, 3);          // the east edge: base, block and base again
  EXPECT_NEAR(party_area, 12 * 4.0 + 8 * 5.0, 1e-6);

  const std::string dir = test::temp_dir("lod13_val3dity");
  test::write_solids_cityjson({{"B1", "1.3", shell}}, dir + "/stepped.city.json");
  const auto invalid = test::val3dity_invalid(dir + "/stepped.city.json");
  C3D_NEED(invalid, "../shared/tools/val3dity not found");
  EXPECT_TRUE(invalid->empty()) << invalid->front();
}

TEST(Lod13, InvalidLod22BuildingTakesItsLayersAndSaysWhy) {
  Building b;
  b.id = "T_b1";
  b.solid_problem = "not_closed: 4 boundary edges";
  std::vector<Vec3> points;
  Building layered = lod13_layers(two_level(points), points);
  ASSERT_TRUE(layered.solid_valid);
  adopt_lod13(b, layered);
  EXPECT_EQ(b.lod, Lod::Lod13);
  EXPECT_TRUE(b.solid_valid);
  EXPECT_EQ(b.lod_note, "LoD 2.2 invalid (not_closed: 4 boundary edges): LoD 1.3 of 2 height layers");
}
