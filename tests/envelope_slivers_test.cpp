// Envelope sub-stage "slivers" alone: a vertex bulging a twentieth of a
// millimetre out of a straight eave makes a sliver triangle whose normal tilts
// past val3dity's 20 degrees; the stage drops it where only the run's two
// faces use it and moves it into the face where a wall corner needs it.

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "core/check/polygon_rules.h"
#include "core/check/solid_check.h"
#include "core/geometry/geometry.h"
#include "core/reconstruct/envelope/slivers.h"

using namespace c3d;
using namespace c3d::envelope;

namespace {

// A face of Cimahi 05764 as the CityJSON export wrote it (metres about its
// centre, facing up): val3dity found a triangle of it tilted 22 degrees
// (error 204). Its first vertex lies 0.03 mm from the line through its
// neighbours, 1.6 and 6.8 mm away.
const Ring3 kCimahiRing{{1.10700, 0.71691, -0.01109}, {1.10170, 0.72111, -0.01059}, {-0.08360, -0.72749, -0.03359},
                        {-0.87590, -0.07509, 0.03391}, {-0.87250, -0.10389, 0.03231}, {-0.69670, -0.24869, 0.01731},
                        {-0.69850, -0.25079, 0.01731}, {-0.08970, -0.74799, -0.03439}, {1.10820, 0.71591, -0.01119}};
const Vec3 kApex = kCimahiRing[0];

bool tilts_on_export(const Face& f) { return tilted_triangle(on_export_grid(f), 20); }

// That face, its plan scaled about the centre, as the top of a prism down to
// z = -3 (walls per edge; one_wall: the two walls meeting under the apex are
// one, so only the top and that wall use it).
std::vector<Face> prism(bool one_wall, double scale = 1) {
  Ring3 top = kCimahiRing;  // the apex first
  for (Vec3& v : top) v.head<2>() *= scale;
  auto down = [](Vec3 v) { return Vec3(v.x(), v.y(), -3); };
  std::vector<Face> faces{Face{top, {}}};
  Ring3 bottom;
  for (auto it = top.rbegin(); it != top.rend(); ++it)
    if (!(one_wall && *it == kApex)) bottom.push_back(down(*it));
  faces.push_back(Face{bottom, {}});
  const size_t n = top.size();
  for (size_t i = 0; i < n; ++i) {
    const Vec3 a = top[i], b = top[(i + 1) % n];
    if (one_wall && a == kApex) continue;  // the next wall holds this edge
    if (one_wall && b == kApex) {
      const Vec3 c = top[(i + 2) % n];
      faces.push_back(Face{{down(a), down(c), c, b, a}, {}});
      continue;
    }
    faces.push_back(Face{{down(a), down(b), b, a}, {}});
  }
  return faces;
}

int uses(const std::vector<Face>& faces, const Vec3& p) {
  int n = 0;
  for (const Face& f : faces) n += int(std::count(f.ring.begin(), f.ring.end(), p));
  return n;
}

std::vector<Element> copies_of(const std::vector<Face>& solid) {
  std::vector<Element> e(1);
  e[0].faces = solid;
  return e;
}

}  // namespace

TEST(EnvelopeSlivers, ARealSliverStopsTiltingAndTheAreaStays) {
  const Face face{kCimahiRing, {}};
  ASSERT_TRUE(tilts_on_export(face));
  std::vector<Face> no_solid;
  std::vector<Element> elements = copies_of({face});
  straighten_slivers(no_solid, elements);
  const Face& after = elements[0].faces.at(0);
  EXPECT_FALSE(tilts_on_export(after));
  EXPECT_NEAR(area(after), area(face), 2e-5);  // m^2
}

TEST(EnvelopeSlivers, TheSolidsAreValidButTheirTopTilts) {
  for (bool one_wall : {false, true}) {
    const std::vector<Face> solid = prism(one_wall);
    const SolidCheck check = check_solid(solid);
    EXPECT_TRUE(check.ok) << check.summary();
    EXPECT_EQ(uses(solid, kApex), one_wall ? 2 : 3);
    EXPECT_TRUE(tilts_on_export(solid[0]));
  }
}

// The solid valid and untilted after the stage, its volume kept, and the
// elements' copies edited alike.
void expect_straightened(const std::vector<Face>& before, const std::vector<Face>& solid,
                         const std::vector<Element>& elements) {
  for (const Face& f : solid) EXPECT_FALSE(tilts_on_export(f));
  const SolidCheck check = check_solid(solid);
  EXPECT_TRUE(check.ok) << check.summary();
  EXPECT_NEAR(check.volume, check_solid(before).volume, 1e-4);
  for (size_t i = 0; i < solid.size(); ++i) EXPECT_EQ(elements[0].faces[i].ring, solid[i].ring) << i;
}

TEST(EnvelopeSlivers, AVertexOnlyTheRunsTwoFacesUseIsDropped) {
  const std::vector<Face> before = prism(true);
  std::vector<Face> solid = before;
  std::vector<Element> elements = copies_of(solid);
  straighten_slivers(solid, elements);
  EXPECT_EQ(uses(solid, kApex), 0);
  EXPECT_EQ(solid[0].ring.size(), kCimahiRing.size() - 1);
  expect_straightened(before, solid, elements);
}

TEST(EnvelopeSlivers, AWallCornerUnderTheRunMergesIntoItsNearNeighbour) {
  const std::vector<Face> before = prism(false);
  std::vector<Face> solid = before;
  std::vector<Element> elements = copies_of(solid);
  straighten_slivers(solid, elements);
  EXPECT_EQ(uses(solid, kApex), 0);
  EXPECT_EQ(solid[0].ring.size(), kCimahiRing.size() - 1);
  // The 1.6 mm wide wall under the short edge is gone: the bottom's corner
  // under the apex had the same sliver and merged the same way.
  const Vec3 neighbour = kCimahiRing.back();
  EXPECT_EQ(uses(solid, neighbour), 3);
  EXPECT_EQ(solid.size(), before.size() - 1);
  expect_straightened(before, solid, elements);
}

TEST(EnvelopeSlivers, AWallCornerFarFromItsNeighboursMovesIntoTheFace) {
  // Eight times wider: the neighbours 13 and 54 mm away, the apex 0.3 mm off their line.
  const std::vector<Face> before = prism(false, 8);
  const Vec3 apex = before[0].ring.front();
  std::vector<Face> solid = before;
  std::vector<Element> elements = copies_of(solid);
  straighten_slivers(solid, elements);
  EXPECT_EQ(uses(solid, apex), 0);
  // Still one vertex of the top and both walls, half a millimetre from where it was.
  const Vec3 moved = solid[0].ring.front();
  EXPECT_NEAR((moved - apex).norm(), 5e-4, 5e-4);
  EXPECT_EQ(uses(solid, moved), 3);
  expect_straightened(before, solid, elements);
}

TEST(EnvelopeSlivers, FacesWithoutSliverTrianglesAreLeftAlone) {
  // A 10 x 8 x 3 m box whose top's front edge bends 0.05 mm out at a wall
  // corner: its triangulation makes no thin triangle there, so nothing moves.
  const Vec3 bend(5, -0.00005, 3);
  const Vec3 p0(0, 0, 0), p1(10, 0, 0), p2(10, 8, 0), p3(0, 8, 0), up(0, 0, 3), mid(5, 0, 0);
  std::vector<Face> solid{Face{{p0, p3, p2, p1, mid}, {}},
                          Face{{p0 + up, bend, p1 + up, p2 + up, p3 + up}, {}},
                          Face{{p0, mid, bend, p0 + up}, {}},
                          Face{{mid, p1, p1 + up, bend}, {}},
                          Face{{p1, p2, p2 + up, p1 + up}, {}},
                          Face{{p2, p3, p3 + up, p2 + up}, {}},
                          Face{{p3, p0, p0 + up, p3 + up}, {}}};
  ASSERT_TRUE(check_solid(solid).ok);
  const std::vector<Face> before = solid;
  std::vector<Element> elements = copies_of(solid);
  straighten_slivers(solid, elements);
  for (size_t i = 0; i < solid.size(); ++i) EXPECT_EQ(solid[i].ring, before[i].ring) << i;
}
