// Envelope sub-stage "roof faces" alone: heights welded at shared vertices,
// pieces lifted onto their planes, and the soffits under the hanging roof.

#include <gtest/gtest.h>

#include <vector>

#include "core/geometry/geometry.h"
#include "core/reconstruct/envelope/roof_faces.h"
#include "tests/reconstruct_fixtures.h"

using namespace c3d;
using namespace c3d::envelope;
using namespace c3d::test;

namespace {

Polygon2 rect(double x0, double y0, double x1, double y1) { return {{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}, {}}; }

}  // namespace

TEST(EnvelopeRoofFaces, HeightsWithinTwoMillimetresWeldToTheirMean) {
  Heights h;
  const Vec2 v(1, 2);
  h.add(v, 5.000);
  h.add(v, 5.001);
  h.add(v, 5.008);
  EXPECT_NEAR(h.get(v, 5.000), 5.0005, 1e-12);  // 5.008 is another line
  EXPECT_NEAR(h.get(v, 5.008), 5.008, 1e-12);
  EXPECT_NEAR(h.get(Vec2(0, 0), 7.0), 7.0, 0);  // no piece there: its own plane
  h.meet_at_mean(v);  // all within 1 cm: every piece at the mean
  EXPECT_NEAR(h.get(v, 5.008), (5.000 + 5.001 + 5.008) / 3, 1e-12);
  Heights far;
  far.add(v, 5.0);
  far.add(v, 5.02);
  far.meet_at_mean(v);  // 2 cm apart: a real step, each keeps its own
  EXPECT_NEAR(far.get(v, 5.02), 5.02, 1e-12);
}

TEST(EnvelopeRoofFaces, FlatFacesDownwardWhenAsked) {
  const Ring2 r = rect(0, 0, 2, 1).outer;
  const Ring3 up = flat(r, 4, false), down = flat(r, 4, true);
  EXPECT_GT(newell_normal(up).z(), 0);
  EXPECT_LT(newell_normal(down).z(), 0);
  for (const Vec3& p : down) EXPECT_EQ(p.z(), 4);
}

TEST(EnvelopeRoofFaces, AMonopitchRoofLiftedWithItsSoffitAtTheLowestEave) {
  // z = 3 + 0.1 x over [0,12] x [0,10]; walls round [1,11] x [1,9].
  const Plane slope = plane_through({0, 0, 3}, {-0.1, 0, 1});
  const std::vector<RoofRegion> roof{RoofRegion{0, slope, {rect(0, 0, 12, 10)}}};
  const std::vector<Piece> pieces{Piece{0, true, rect(1, 1, 11, 9)},
                                  Piece{0, false, Polygon2{rect(0, 0, 12, 10).outer, {rect(1, 1, 11, 9).outer}}}};
  const RoofFaces faces = lift_roof(pieces, roof);
  ASSERT_EQ(faces.by_region.size(), 1u);
  EXPECT_EQ(faces.by_region[0].size(), 2u);
  ASSERT_EQ(faces.inside.size(), 1u);
  EXPECT_EQ(faces.inside_region, std::vector<int>{0});
  for (const Vec3& p : faces.inside[0].ring) EXPECT_NEAR(p.z(), 3 + 0.1 * p.x(), 1e-12);
  ASSERT_EQ(faces.soffits.size(), 1u);
  const Face& s = faces.soffits[0];
  for (const Vec3& p : s.ring) EXPECT_NEAR(p.z(), 3.0, 1e-12);  // the lowest eave, at x = 0
  EXPECT_LT(unit_normal(s).z(), -0.99);                           // faces down
  EXPECT_NEAR(plan_area(s), 120 - 80, 1e-9);
  // The roof's plan area is the inside and hanging pieces' together.
  EXPECT_NEAR(plan_area(faces.by_region[0][0]) + plan_area(faces.by_region[0][1]), 120, 1e-9);
}

TEST(EnvelopeRoofFaces, TwoPlanesMissingAVertexByAMillimetreMeetThere) {
  // Two flat pieces side by side, 1 mm apart in height: welded at their
  // shared vertices, so no step wall a millimetre high stands between them.
  const std::vector<RoofRegion> roof{RoofRegion{0, plane_through({0, 0, 3.000}, {0, 0, 1}), {rect(0, 0, 5, 4)}},
                                     RoofRegion{1, plane_through({0, 0, 3.001}, {0, 0, 1}), {rect(5, 0, 10, 4)}}};
  const RoofFaces faces = lift_roof({Piece{0, true, rect(0, 0, 5, 4)}, Piece{1, true, rect(5, 0, 10, 4)}}, roof);
  ASSERT_EQ(faces.inside.size(), 2u);
  for (const Face& f : faces.inside)
    for (const Vec3& p : f.ring)
      if (p.x() == 5) EXPECT_NEAR(p.z(), 3.0005, 1e-12);
}
