// Own geometry validator (val3dity rules): the fixtures pass, and each rule catches
// the defect it is meant for, reported with the building id and val3dity's code.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <fstream>
#include <set>

#include <nlohmann/json.hpp>

#include "core/check/polygon_rules.h"
#include "ifc_citygml/export.h"
#include "ifc_citygml/validate.h"
#include "tests/export_checks.h"
#include "tests/export_fixtures.h"
#include "tests/test_support.h"

using namespace c3d;
namespace fx = c3d::fixture;

namespace {

bool has_code(const std::vector<ValidationIssue>& v, int code) {
  return std::any_of(v.begin(), v.end(), [&](const auto& i) { return i.code == code; });
}

std::string dump(const std::vector<ValidationIssue>& v) {
  std::string s;
  for (const auto& i : v) s += to_string(i) + "\n";
  return s;
}

Building gable() { return fx::gable_house("G_b1"); }

}  // namespace

TEST(Validate, FixturesAreValid) {
  auto m = fx::sample_batch();
  auto issues = validate_model(m);
  EXPECT_TRUE(issues.empty()) << dump(issues);
}

TEST(Validate, OpenShell) {
  Building b = gable();
  b.solid.pop_back();
  auto v = validate_building(b);
  ASSERT_TRUE(has_code(v, kShellNotClosed)) << dump(v);
  EXPECT_EQ(v.front().building_id, "G_b1");
}

TEST(Validate, FlippedFace) {
  Building b = gable();
  std::reverse(b.solid[2].ring.begin(), b.solid[2].ring.end());
  auto v = validate_building(b);
  ASSERT_TRUE(has_code(v, kPolygonWrongOrientation)) << dump(v);
  EXPECT_NE(dump(v).find("solid face 2"), std::string::npos) << dump(v);
}

TEST(Validate, AllFacesInward) {
  Building b = gable();
  for (auto& f : b.solid) std::reverse(f.ring.begin(), f.ring.end());
  auto v = validate_building(b);
  EXPECT_TRUE(has_code(v, kPolygonWrongOrientation)) << dump(v);
}

TEST(Validate, NonPlanarFace) {
  Building b = gable();
  b.solid[5].ring[2].z() += 0.2;  // one roof corner lifted: ~4 cm off the fitted plane
  auto v = validate_building(b);
  EXPECT_TRUE(has_code(v, kNonPlanarDistancePlane)) << dump(v);
  b = gable();
  b.solid[5].ring[2].z() += 0.005;  // within the 1 cm tolerance
  EXPECT_FALSE(has_code(validate_building(b), kNonPlanarDistancePlane));
}

TEST(Validate, DuplicateAndDegenerateRings) {
  Building b = gable();
  b.solid[1].ring.insert(b.solid[1].ring.begin() + 1, b.solid[1].ring[1]);
  EXPECT_TRUE(has_code(validate_building(b), kConsecutivePointsSame));
  b = gable();
  b.elements[0].faces[0].ring = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};  // collinear: zero area
  EXPECT_TRUE(has_code(validate_building(b), kRingSelfIntersection));
  b = gable();
  b.elements[2].faces[0].ring = {{0, 0, 0}, {10, 0, 3}, {10, 0, 0}, {0, 0, 3}};  // bow tie
  EXPECT_TRUE(has_code(validate_building(b), kRingSelfIntersection));
  b = gable();
  b.elements[2].faces[0].ring = {{0, 0, 0}, {10, 0, 0}};
  EXPECT_TRUE(has_code(validate_building(b), kTooFewPoints));
}

TEST(Validate, TooFewPolygonsAndNonManifold) {
  Building b = gable();
  b.solid.resize(3);
  EXPECT_TRUE(has_code(validate_building(b), kTooFewPolygons));
  b = gable();
  b.solid.push_back(fx::face({{0, 0, 0}, {10, 0, 0}, {5, -4, 0}}));  // third face on an edge
  EXPECT_TRUE(has_code(validate_building(b), kNonManifoldCase)) << dump(validate_building(b));
}

TEST(Validate, ShellSelfIntersection) {
  // Closed, manifold, positive volume, but the lower cone pokes through the upper one.
  Vec3 A(0, 0, 0), B(10, 0, 0), C(0, 10, 0), P(10.0 / 3, 10.0 / 3, 10), Q(8, 8, 5);
  Building b;
  b.id = "X_b1";
  b.solid = {fx::face({P, A, B}), fx::face({P, B, C}), fx::face({P, C, A}),
             fx::face({Q, B, A}), fx::face({Q, C, B}), fx::face({Q, A, C})};
  auto v = validate_building(b);
  EXPECT_TRUE(has_code(v, kShellSelfIntersection)) << dump(v);
}

TEST(ValidateCli, CityJsonFileGoodAndBroken) {
  std::string dir = test::temp_dir("validate_cli");
  auto m = fx::sample_batch();
  write_cityjson(m, dir + "/good.city.json");
  std::string out;
  EXPECT_EQ(test::run_cli("validate " + dir + "/good.city.json", &out), 0) << out;
  std::reverse(m.results[0].buildings[0].solid[1].ring.begin(),
               m.results[0].buildings[0].solid[1].ring.end());
  write_cityjson(m, dir + "/flipped.city.json");
  EXPECT_EQ(test::run_cli("validate " + dir + "/flipped.city.json", &out), 1) << out;
  EXPECT_NE(out.find("P-001_b1"), std::string::npos) << out;
  EXPECT_NE(out.find("307"), std::string::npos) << out;
}

TEST(ExportCli, FromCityJsonToEveryFormat) {
  std::string dir = test::temp_dir("export_cli");
  write_cityjson(fx::sample_batch(), dir + "/in.city.json");
  std::string out;
  ASSERT_EQ(test::run_cli("export --store " + dir + "/in.city.json --out " + dir +
                              "/out --formats gml,cityjson,ifc,obj,step",
                          &out),
            0)
      << out;
  for (const char* f : {"buildings.gml", "buildings.city.json", "buildings.ifc", "obj/P-001.obj",
                        "step/P-004_b1.step"})
    EXPECT_TRUE(std::filesystem::exists(dir + "/out/" + f)) << f << "\n" << out;
  EXPECT_EQ(test::run_cli("export --store " + dir + "/in.city.json --out " + dir +
                              "/out2 --formats nonsense",
                          &out),
            2)
      << out;
}

TEST(Validate, CollinearWallTopPiecesAreNotACrossing) {
  // A wall under one roof plane with a small step up in the middle (as on Cimahi
  // parcel 05787): the two top edges either side of the step lie on the same
  // roof-plane line, at UTM magnitudes. They touch nowhere, so the ring is valid.
  const Vec3 o(781836.8593649674, 9240021.244433638, 782.42776);
  const Vec3 along = Vec3(1.62, 1.98, 0).normalized();
  auto at = [&](double s, double z) { return Vec3(o + s * along + Vec3(0, 0, z)); };
  const double slope = 0.0014;  // the roof line's rise along the wall
  Face wall = fx::face({at(6.4, 0), at(0, 0), at(0, 9.08), at(2.56, 9.08 + 2.56 * slope),
                        at(2.56, 9.33), at(2.93, 9.12), at(3.0, 9.08 + 3.0 * slope),
                        at(4.64, 9.08 + 4.64 * slope), at(4.64, 8.18), at(6.4, 7.3)});
  Building b = gable();
  b.elements[2].faces[0] = wall;
  auto v = validate_building(b);
  EXPECT_FALSE(has_code(v, kRingSelfIntersection)) << dump(v);
  // The same ring with the step folded back over the first piece does cross.
  wall.ring[6] = at(2.0, 9.08 + 2.0 * slope + 0.001);
  wall.ring[5] = at(2.2, 9.2);
  b.elements[2].faces[0] = wall;
  EXPECT_TRUE(has_code(validate_building(b), kRingSelfIntersection)) << dump(validate_building(b));
}

// The issues and their codes of one face under validate's default rules.
std::vector<PolygonIssue> issues_of(const Face& f) {
  VertexSnap snap(PolygonRules{}.snap_tol);
  std::vector<std::vector<int>> rings;
  std::vector<PolygonIssue> issues;
  check_polygon(f, PolygonRules{}, snap, rings, issues);
  return issues;
}

std::vector<int> codes_of(const Face& f) {
  std::vector<int> codes;
  for (const auto& i : issues_of(f)) codes.push_back(i.code);
  return codes;
}

TEST(PolygonRules, ThinFaceCanTiltOnTheExportGrid) {
  // A roof face of a Cimahi house (parcels laid out on an 18 m grid): three
  // near-collinear vertices along its north edge form a triangle under 1 mm
  // thick that lies flat; rounded to CityJSON's 0.1 mm grid it is tilted,
  // and `validate` rejects the face there.
  const Face face{{{32.938274782570005, 80.261119695303648, 789.91594052795597},
                   {33.538592362529215, 76.034388426364799, 791.66262839905494},
                   {33.576039830877257, 76.007004576426354, 791.66254261953998},
                   {33.603638795453179, 75.988943745539018, 791.66215807441995},
                   {36.107280833167096, 76.381875053795142, 790.62949533116353},
                   {36.142307986220032, 76.387372351278685, 790.61505708444224},
                   {36.180362702009951, 76.144898961699155, 790.71402992046569},
                   {36.49151387441659, 75.924101438789052, 790.71020893982086},
                   {36.49151387441659, 77.666687359903804, 789.9059964783919}},
                  {}};
  EXPECT_TRUE(issues_of(face).empty());
  const Face exported = on_export_grid(face);
  const auto there = issues_of(exported);
  ASSERT_EQ(there.size(), 1u);
  EXPECT_EQ(there.front().code, kNonPlanarNormalsDeviation);
  for (size_t i = 0; i < face.ring.size(); ++i)
    EXPECT_LE((exported.ring[i] - face.ring[i]).cwiseAbs().maxCoeff(), kExportGridM / 2 + 1e-12);
}

TEST(PolygonRules, NeighboursUnderAMillimetreApartRepeatAcrossAGridBorder) {
  // val3dity merges a vertex into the first one within 1 mm, by distance; two
  // consecutive vertices 0.6 mm apart on either side of a 1 mm grid border
  // (x = 5.0012 and 5.0018) are one vertex there: a repeated point (102).
  const Face close{{{0, 0, 3}, {5.0012, 0, 3}, {5.0018, 0, 3}, {5, 4, 3}, {0, 4, 3}}, {}};
  EXPECT_EQ(codes_of(close), std::vector<int>{kConsecutivePointsSame});
  const Face apart{{{0, 0, 3}, {5.0012, 0, 3}, {5.0032, 0.5, 3}, {5, 4, 3}, {0, 4, 3}}, {}};
  EXPECT_TRUE(codes_of(apart).empty());
}

TEST(PolygonRules, AVertexUnderAMillimetreFromAnotherFacesTiltsItOnceSnapped) {
  // A 2 mm wide flat strip, and a wall whose corner sits 0.9 mm above the
  // strip's: val3dity merges the strip's corner into the wall's (read first).
  const Face wall{{{0.15, 0.002, 0.0009}, {0.15, 0.002, -3}, {0.15, 1, -3}, {0.15, 1, 0}}, {}};
  const Face strip{{{0, 0, 0}, {0.15, 0, 0}, {0.15, 0.002, 0}, {0, 0.002, 0}}, {}};
  EXPECT_TRUE(codes_of(strip).empty());
  const std::vector<Face> read = snapped_together({wall, strip}, PolygonRules{}.snap_tol);
  EXPECT_EQ(read[1].ring[2], wall.ring[0]);
  EXPECT_EQ(codes_of(read[1]), std::vector<int>{kNonPlanarNormalsDeviation});
  EXPECT_EQ(read[0].ring, wall.ring);  // the first read keeps its own
}

namespace {

// The sample batch and, each on a parcel of its own, gable houses with one
// defect each: the verdicts val3dity and `cadastre3d validate` must share.
BatchModel with_defects() {
  BatchModel m = fx::sample_batch();
  auto add = [&](const std::string& pid, Building b) {
    fx::translate(b, {100.0 * double(m.parcels.size()), 100, 0});
    m.parcels.push_back(fx::parcel(int(m.parcels.size()), pid, m.frame.origin, 0, 1, 0, 1));
    m.results.push_back(fx::result(m.parcels.back(), {b}));
  };
  Building open = fx::gable_house("D-open_b1");
  open.solid.pop_back();
  add("D-open", open);
  Building flipped = fx::gable_house("D-flipped_b1");
  std::reverse(flipped.solid[2].ring.begin(), flipped.solid[2].ring.end());
  add("D-flipped", flipped);
  Building bent = fx::gable_house("D-bent_b1");
  bent.solid[5].ring[2].z() += 0.2;  // ~4 cm off its plane
  add("D-bent", bent);
  Building lod = fx::gable_house("D-lod_b1");
  LodShell prism;
  prism.lod = Lod::Lod12;
  prism.faces = test::box_shell({0, 0, 0}, {10, 8, 4});
  prism.faces.pop_back();  // the LoD 1.2 shell is open
  prism.face_types.assign(prism.faces.size(), ElementType::Wall);
  lod.lower_lods = {prism};
  add("D-lod", lod);
  return m;
}

}  // namespace

TEST(Val3dityJudge, AgreesWithValidateOnEveryBuilding) {
  // The same CityJSON file judged by both, building by building: the valid
  // buildings pass both, each defect (open shell, flipped face, bent roof, an
  // open lower LoD) fails both.
  const std::string dir = test::temp_dir("judge"), path = dir + "/judged.city.json";
  write_cityjson(with_defects(), path);
  const auto judged = test::val3dity_invalid(path);
  C3D_NEED(judged, "../shared/tools/val3dity not found");
  const std::set<std::string> val3dity(judged->begin(), judged->end());
  std::string log;
  const std::set<std::string> ours = check::validate_invalid(path, &log);
  const std::set<std::string> defects{"D-open_b1", "D-flipped_b1", "D-bent_b1", "D-lod_b1"};
  EXPECT_EQ(val3dity, defects);
  EXPECT_EQ(ours, val3dity) << log;
}

namespace {

// A 2 x 2 x 1 box with a pit in its top: the top face's hole (the pit's rim)
// touches the face's outer ring at T = (1, 2, 1), a vertex of the wall y = 2
// too. Valid for OGC and val3dity (AHN3 09395's roof has such a hole).
nlohmann::json box_with_pit_touching_the_rim() {
  const std::vector<std::array<int, 3>> v = {{0, 0, 0},    {2000, 0, 0},    {2000, 2000, 0},   {0, 2000, 0},
                                             {0, 0, 1000}, {2000, 0, 1000}, {2000, 2000, 1000}, {0, 2000, 1000},
                                             {1000, 2000, 1000}, {1500, 1000, 1000}, {500, 1000, 1000},
                                             {1000, 1300, 500}};
  enum { a, b, c, d, e, f, g, h, T, A, B, D };
  const nlohmann::json shell = {{{a, d, c, b}},       {{a, b, f, e}}, {{b, c, g, f}}, {{c, d, h, T, g}},
                                {{d, a, e, h}},       {{e, f, g, T, h}, {T, A, B}},
                                {{T, B, D}},          {{B, A, D}},    {{A, T, D}}};
  return {{"type", "CityJSON"},
          {"version", "2.0"},
          {"transform", {{"scale", {0.001, 0.001, 0.001}}, {"translate", {0, 0, 0}}}},
          {"CityObjects",
           {{"pit_b1", {{"type", "Building"}, {"geometry", {{{"type", "Solid"}, {"lod", "2"}, {"boundaries", {shell}}}}}}}}},
          {"vertices", v}};
}

}  // namespace

TEST(Val3dityJudge, AHoleTouchingItsOuterRingIsNoPinch) {
  // Around T the faces form two fans joined through the top face: one fan,
  // as val3dity sees it. Two boxes meeting at a corner stay two fans.
  const std::string dir = test::temp_dir("pit"), path = dir + "/pit.city.json", pinch = dir + "/pinch.city.json";
  nlohmann::json doc = box_with_pit_touching_the_rim();
  std::ofstream(path) << doc.dump();
  nlohmann::json& shell = doc["CityObjects"]["pit_b1"]["geometry"][0]["boundaries"][0];
  shell = nlohmann::json::array();  // the box twice, the second moved to touch the first's corner
  const int n = int(doc["vertices"].size());
  for (int k = 0; k < 8; ++k) {
    auto q = doc["vertices"][size_t(k)];
    doc["vertices"].push_back({q[0].get<int>() + 2000, q[1].get<int>() + 2000, q[2].get<int>() + 1000});
  }
  for (int off : {0, n})
    for (const auto& r : std::vector<std::array<int, 4>>{{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                                          {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}})
      shell.push_back({{r[0] + off, r[1] + off, r[2] + off, r[3] + off}});
  std::ofstream(pinch) << doc.dump();
  std::string log;
  EXPECT_TRUE(check::validate_invalid(path, &log).empty()) << log;
  EXPECT_EQ(check::validate_invalid(pinch, &log), std::set<std::string>{"pit_b1"}) << log;
  const auto judged = test::val3dity_invalid(path);
  C3D_NEED(judged, "../shared/tools/val3dity not found");
  EXPECT_TRUE(judged->empty());
  EXPECT_EQ(*test::val3dity_invalid(pinch), std::vector<std::string>{"pit_b1"});
}
