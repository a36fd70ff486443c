// The evaluate logic called as a library (core/evaluate, cadastre/evaluate), not
// through the CLI: faces sorted into roof and wall, class codes, zones matched to
// parcels by name and by place, the batch's ruler for roof and wall points, the
// pooled statistics and what is written out, on boxes with known distances.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "cadastre/evaluate/parcel_evaluation.h"
#include "core/error.h"
#include "core/evaluate/evaluation_output.h"
#include "core/evaluate/model_surfaces.h"
#include "core/evaluate/zones.h"
#include "tests/test_support.h"

using namespace c3d;

namespace {

const Vec3 kO(512300.0, 9241200.0, 700.0);  // UTM-sized coordinates
// Offsets of the roof points from the roof, and their exact statistics.
const std::vector<double> kOffsets{0.1, -0.2, 0.3, 0.4, -0.5};
constexpr double kMean = 0.3, kMeanSq = 0.11;

Face quad(Vec3 a, Vec3 b, Vec3 c, Vec3 d) { return {{a, b, c, d}, {}}; }

// A 10 x 8 x 3 m box at kO + (x0, 0, 0) as the batch's OBJ groups name it.
std::vector<MeshGroup> box_house(const std::string& parcel, double x0, double x1) {
  auto b = test::box_shell(kO + Vec3(x0, 0, 0), kO + Vec3(x1, 8, 3));
  return {{parcel + "_b1_roof", "", {b[1]}},
          {parcel + "_b1_wall", "", {b[2], b[3], b[4], b[5]}},
          {parcel + "_b1_ground", "", {b[0]}}};
}

Parcel square(const std::string& id, double x0, double x1) {
  Parcel p;
  p.id = id;
  const double y0 = kO.y() - 1, y1 = kO.y() + 9;
  p.shape = {{{{kO.x() + x0, y0}, {kO.x() + x1, y0}, {kO.x() + x1, y1}, {kO.x() + x0, y1}}, {}}};
  return p;
}

ParcelLayer layer_of(std::vector<Parcel> parcels) {
  for (size_t i = 0; i < parcels.size(); ++i) parcels[i].index = int(i);
  ParcelLayer layer;
  layer.parcels = std::move(parcels);
  return layer;
}

// P1's house; five roof points at kOffsets over its roof, two wall points 0.2 m
// off its west and north walls, and a roof point in P2 (x 20..30), which has no model.
RoofWallPoints house_points() {
  RoofWallPoints pts;
  for (size_t i = 0; i < kOffsets.size(); ++i)
    pts.roof.push_back(kO + Vec3(1 + 1.5 * double(i), 2 + double(i), 3 + kOffsets[i]));
  pts.roof.push_back(kO + Vec3(25, 4, 3));
  pts.wall = {kO + Vec3(-0.2, 4, 1.5), kO + Vec3(5, 8.2, 1)};
  return pts;
}

ModelEvaluation house_per_parcel() {
  return evaluate_per_parcel(box_house("P1", 0, 10), house_points(),
                             layer_of({square("P1", -1, 11), square("P2", 20, 30)}));
}

}  // namespace

TEST(EvaluateModel, SurfacesByLabelElseByNormal) {
  const Face flat = quad({0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0});
  const Face upright = quad({0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1});
  EXPECT_EQ(surface_kind({"P1_b1_Roof", "", {}}, upright), SurfaceKind::Roof);  // the label wins
  EXPECT_EQ(surface_kind({"", "wall", {}}, flat), SurfaceKind::Wall);
  EXPECT_EQ(surface_kind({"P1_b1_ground", "", {}}, flat), SurfaceKind::Other);
  EXPECT_EQ(surface_kind({"x", "", {}}, flat), SurfaceKind::Roof);
  EXPECT_EQ(surface_kind({"x", "", {}}, upright), SurfaceKind::Wall);
  const Face facing_down = quad({0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0});
  EXPECT_EQ(surface_kind({"x", "", {}}, facing_down), SurfaceKind::Other);
}

TEST(EvaluateModel, ClassCodesAndPointsByClass) {
  const ClassMapping m = parse_class_codes("roof=6,roof=7,wall=64", "--classes");
  EXPECT_EQ(m.roof, (std::vector<int>{6, 7}));
  EXPECT_EQ(m.wall, (std::vector<int>{64}));
  EXPECT_THROW(parse_class_codes("roof6", "--classes"), InputError);
  EXPECT_THROW(parse_class_codes("door=6", "--classes"), InputError);

  PointCloud cloud;
  cloud.points = {{0, 0, 1}, {0, 0, 2}, {0, 0, 3}, {0, 0, 4}};
  cloud.classes = {6, 64, 2, 7};
  const RoofWallPoints p = roof_and_wall_points(cloud, m);
  EXPECT_FALSE(p.unclassified);
  EXPECT_EQ(p.roof, (std::vector<Vec3>{{0, 0, 1}, {0, 0, 4}}));
  EXPECT_EQ(p.wall, (std::vector<Vec3>{{0, 0, 2}}));
  cloud.classes.clear();  // no classes: every point a roof point
  const RoofWallPoints all = roof_and_wall_points(cloud, m);
  EXPECT_TRUE(all.unclassified);
  EXPECT_EQ(all.roof.size(), 4u);
  EXPECT_TRUE(all.wall.empty());
}

TEST(EvaluateModel, CopiesOfAPointCountOnceAsInTheBatch) {
  // A writer that repeats records: each roof and wall point twice (the second
  // 1 mm off, float rounding). The batch folds copies within kSamePlaceM of
  // each class into one place; `evaluate` must count the same points.
  const ClassMapping m = parse_class_codes("roof=6,wall=64", "--classes");
  PointCloud cloud;
  cloud.points = {{0, 0, 5}, {1, 0, 5}, {0, 0, 5.001}, {1, 0, 5}, {2, 0, 3}, {2, 0, 3}, {0, 0, 5}};
  cloud.classes = {6, 6, 6, 6, 64, 64, 64};
  const RoofWallPoints p = roof_and_wall_points(cloud, m);
  EXPECT_EQ(p.roof, (std::vector<Vec3>{{0, 0, 5}, {1, 0, 5}}));
  // a wall point at a roof point's place is a place of the wall class: kept
  EXPECT_EQ(p.wall, (std::vector<Vec3>{{2, 0, 3}, {0, 0, 5}}));
}

TEST(EvaluateModel, ElementGroupsInWorldCoordinates) {
  BatchModel model;
  model.frame.origin = kO;
  ParcelResult r;
  r.parcel_id = "P1";
  Building b;
  b.id = "P1_b1";
  b.elements.push_back({ElementType::Roof, {quad({0, 0, 3}, {1, 0, 3}, {1, 1, 3}, {0, 1, 3})}});
  r.buildings.push_back(b);
  model.results.push_back(r);
  const auto groups = element_groups(model);
  ASSERT_EQ(groups.size(), 1u);
  EXPECT_EQ(groups[0].name, "P1_P1_b1_" + std::string(to_string(ElementType::Roof)));
  EXPECT_EQ(groups[0].faces[0].ring[2], kO + Vec3(1, 1, 3));
}

TEST(EvaluateModel, OneZoneMeasuresEveryPoint) {
  const ModelEvaluation e = evaluate_as_one_zone(box_house("P1", 0, 10), house_points());
  ASSERT_EQ(e.zones.size(), 1u);
  EXPECT_FALSE(e.per_parcel);
  const ZoneSummary s = summarize(e.zones[0]);
  EXPECT_EQ(s.id, "all");
  EXPECT_EQ(s.roof.n, 6);  // without parcels the P2 point counts too...
  EXPECT_EQ(s.roof_cover.uncovered.n, 1);  // ... with no roof over it, 15 m off the roof's east edge
  EXPECT_NEAR(s.roof_cover.uncovered.rmse, 15.0, 1e-9);
  EXPECT_EQ(s.roof_cover.on_model.n + s.roof_cover.off_model.n, 5);
  EXPECT_EQ(s.roof_faces, 1u);  // the ground is neither roof nor wall
  EXPECT_EQ(s.wall_faces, 4u);
  EXPECT_EQ(s.wall.n, 2);
  EXPECT_NEAR(s.wall.rmse, 0.2, 1e-9);
  EXPECT_EQ(e.points_outside, 0);
}

TEST(EvaluateModel, PerParcelTheBatchsRuler) {
  const ModelEvaluation e = house_per_parcel();
  ASSERT_EQ(e.zones.size(), 2u);
  EXPECT_TRUE(e.per_parcel);
  EXPECT_EQ(e.roof_points, 6u);
  EXPECT_EQ(e.wall_points, 2u);
  const EvaluationSummary s = summarize(e);
  const ZoneSummary& p1 = s.zones[0];
  EXPECT_EQ(p1.id, "P1");
  EXPECT_EQ(p1.roof.n, 5);
  EXPECT_NEAR(p1.roof.mean, kMean, 1e-9);
  EXPECT_NEAR(p1.roof.rmse, std::sqrt(kMeanSq), 1e-9);
  EXPECT_NEAR(p1.roof_vertical.rmse, std::sqrt(kMeanSq), 1e-9);
  EXPECT_EQ(p1.wall.n, 2);
  EXPECT_EQ(p1.wall_cover.on_wall.n, 2);
  EXPECT_EQ(s.zones[1].roof.n, 0);  // P2 has no model: its point is unmodelled
  EXPECT_EQ(s.zones[1].unmodelled_roof, 1);
  EXPECT_EQ(s.pooled.id, "pooled");
  EXPECT_EQ(s.pooled.roof.n, 5);
  EXPECT_EQ(s.pooled.unmodelled_roof, 1);
  EXPECT_EQ(e.points_outside, 0);
  EXPECT_EQ(e.faces_outside, 0);
}

TEST(EvaluateModel, FacesByPlaceAndWhatNoParcelTakes) {
  auto model = box_house("P1", 0, 10);
  // A roof in no group named after a parcel, over P2; another over no parcel.
  model.push_back(
      {"", "", {quad(kO + Vec3(22, 0, 3), kO + Vec3(28, 0, 3), kO + Vec3(28, 8, 3), kO + Vec3(22, 8, 3))}});
  model.push_back(
      {"stray", "", {quad(kO + Vec3(50, 0, 3), kO + Vec3(52, 0, 3), kO + Vec3(52, 2, 3), kO + Vec3(50, 2, 3))}});
  RoofWallPoints pts;
  pts.roof = {kO + Vec3(25, 4, 3.2),  // P2, 0.2 m over its roof
              kO + Vec3(12, 4, 3),    // in P1's reach only: roof points count inside a parcel
              kO + Vec3(15, 4, 3)};   // in no parcel's reach
  pts.wall = {kO + Vec3(12, 4, 1)};   // in P1's reach: 2 m from its east wall, under no roof
  const ModelEvaluation e =
      evaluate_per_parcel(model, pts, layer_of({square("P1", -1, 11), square("P2", 20, 30)}));
  const EvaluationSummary s = summarize(e);
  EXPECT_EQ(s.zones[1].roof_faces, 1u);
  EXPECT_EQ(s.zones[1].roof.n, 1);
  EXPECT_NEAR(s.zones[1].roof.mean, 0.2, 1e-9);
  EXPECT_EQ(e.faces_outside, 1);
  EXPECT_EQ(e.points_outside, 2);
  EXPECT_EQ(s.zones[0].wall.n, 1);
  EXPECT_NEAR(s.zones[0].wall.rmse, 2.0, 1e-9);
  EXPECT_EQ(s.zones[0].wall_cover.under_no_roof.n, 1);
}

TEST(EvaluateModel, TheLongestParcelIdNamesTheGroup) {
  // "A_1_b1_roof" starts with "A_" and "A_1_": it is A_1's, though it lies over A.
  auto model = box_house("A_1", 0, 10);
  RoofWallPoints pts;
  pts.roof = {kO + Vec3(5, 4, 3.1)};
  const ModelEvaluation e =
      evaluate_per_parcel(model, pts, layer_of({square("A", -1, 11), square("A_1", 100, 110)}));
  const EvaluationSummary s = summarize(e);
  EXPECT_EQ(s.zones[0].roof_faces, 0u);
  EXPECT_EQ(s.zones[0].unmodelled_roof, 1);
  EXPECT_EQ(s.zones[1].roof_faces, 1u);
  EXPECT_EQ(s.zones[1].wall_faces, 4u);
}

TEST(EvaluateModel, WallPointsUnderOwnAnotherOrNoRoof) {
  auto model = box_house("P1", 0, 10), second = box_house("P2", 12, 20);
  model.insert(model.end(), second.begin(), second.end());
  RoofWallPoints pts;
  pts.wall = {kO + Vec3(-0.2, 4, 1.5),  // 0.2 m off P1's west wall
              kO + Vec3(5, 4, 1),       // under P1's roof, 4 m from every wall
              kO + Vec3(12.5, 4, 1),    // under P2's roof: 2.5 m from P1's east wall, 0.5 m from P2's west wall
              kO + Vec3(5, 10, 1)};     // 1 m off P1's land, under no roof, 2 m from P1's north wall
  const ModelEvaluation e =
      evaluate_per_parcel(model, pts, layer_of({square("P1", -1, 11), square("P2", 11.5, 21)}));
  const WallCover p1 = summarize(e.zones[0]).wall_cover;
  EXPECT_EQ(p1.on_wall.n, 1);
  EXPECT_NEAR(p1.on_wall.max, 0.2, 1e-9);
  EXPECT_NEAR(p1.under_own_roof.max, 4.0, 1e-9);
  EXPECT_NEAR(p1.under_other_roof.max, 2.5, 1e-9);
  EXPECT_NEAR(p1.under_no_roof.max, 2.0, 1e-9);
  const WallCover p2 = summarize(e.zones[1]).wall_cover;
  EXPECT_EQ(p2.under_own_roof.n, 1);  // the point under its roof, 0.5 m inside its wall
  EXPECT_EQ(summarize(e).pooled.wall_cover.under_own_roof.n, 2);
}

TEST(EvaluateModel, JsonTableAndResiduals) {
  const ModelEvaluation e = house_per_parcel();
  const EvaluationSummary s = summarize(e);
  const nlohmann::json j = evaluation_json(e, s);
  EXPECT_EQ(j["parcels"][0]["id"], "P1");
  EXPECT_EQ(j["parcels"][0]["wall_cover"]["on_wall"]["n"], 2);
  EXPECT_EQ(j["parcels"][1]["unmodelled_roof_points"], 1);
  EXPECT_EQ(j["pooled"]["roof"]["n"], 5);
  EXPECT_EQ(j["points_outside_parcels"], 0);
  EXPECT_FALSE(evaluation_json(evaluate_as_one_zone({}, {}), s).contains("parcels"));

  const std::string table = evaluation_table(e, s);
  EXPECT_EQ(table.rfind("parcel ", 0), 0u);
  EXPECT_NE(table.find("\nP1 "), std::string::npos) << table;
  EXPECT_NE(table.find("\npooled "), std::string::npos) << table;
  EXPECT_NE(table.find("roof points 6, wall points 2; in parcels without a model: 1 roof, 0 wall"),
            std::string::npos)
      << table;

  const std::string dir = test::temp_dir("residuals");
  write_residuals_csv(dir + "/r.csv", e.zones);
  std::ifstream in(dir + "/r.csv");
  std::vector<std::string> rows;
  for (std::string line; std::getline(in, line);) rows.push_back(line);
  ASSERT_EQ(rows.size(), 8u);  // the header, P1's 5 roof and 2 wall points; P2 has no model
  EXPECT_EQ(rows[0], "parcel,kind,x,y,z,distance_m,vertical_m,part");
  EXPECT_EQ(rows[1], "P1,roof,512301.000,9241202.000,703.100,0.1000,0.1000,on_model");
  EXPECT_EQ(rows[6], "P1,wall,512299.800,9241204.000,701.500,0.2000,,on_wall");
  EXPECT_THROW(write_residuals_csv(dir + "/no/such/dir.csv", e.zones), InputError);
}
