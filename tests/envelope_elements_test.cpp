// Envelope sub-stage "elements" alone: faces grouped into roof, ground and
// outer ceiling elements with known areas, directions and uncertainties.

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/geometry/geometry.h"
#include "core/reconstruct/envelope/elements.h"
#include "tests/reconstruct_fixtures.h"

using namespace c3d;
using namespace c3d::envelope;
using namespace c3d::test;

namespace {

Polygon2 rect(double x0, double y0, double x1, double y1) { return {{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}, {}}; }

// The plan ring lifted onto `plane`.
Face on_plane(const Ring2& r, const Plane& plane) {
  Face f;
  for (const Vec2& v : r) f.ring.emplace_back(v.x(), v.y(), plane.z_at(v.x(), v.y()));
  return f;
}

}  // namespace

TEST(EnvelopeElements, AreasSumOverFacesAndAnOuterCeilingCountsItsPlan) {
  // A roof face rising 1 in 1 towards north over 4 x 3 m: 12 m^2 of plan, 12 sqrt(2) of roof.
  const Face tilted = on_plane(rect(0, 0, 4, 3).outer, plane_through({0, 0, 3}, {0, -1, 1}));
  const Element roof = make_element(ElementType::Roof, {tilted, tilted});
  EXPECT_NEAR(roof.area, 2 * 12 * std::sqrt(2.0), 1e-9);
  EXPECT_NEAR(roof.plan_area, 24, 1e-9);
  const Element ceiling = make_element(ElementType::OuterCeiling, {tilted});
  EXPECT_NEAR(ceiling.area, 12, 1e-9);
}

TEST(EnvelopeElements, AzimuthIsWhereTheNormalPoints) {
  const Face south{{{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}}, {}};
  const Face east{{{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}}, {}};
  EXPECT_NEAR(azimuth_of(south), 180, 1e-9);
  EXPECT_NEAR(azimuth_of(east), 90, 1e-9);
  Element e = make_element(ElementType::Wall, {south, Face{{{0, 0, 0}, {3, 0, 0}, {3, 0, 1}, {0, 0, 1}}, {}}});
  EXPECT_NEAR(area(widest_face(e)), 3, 1e-12);
  EXPECT_NEAR(perimeter(rect(0, 0, 3, 4).outer), 14, 1e-12);
}

TEST(EnvelopeElements, RoofElementsOnePerRegionWithFaces) {
  const Plane south = plane_through({0, 5, 8}, {0, -1, 1}), flat = plane_through({0, 0, 3}, {0, 0, 1});
  const std::vector<RoofRegion> roof{RoofRegion{0, south, {rect(0, 0, 4, 5)}}, RoofRegion{1, flat, {rect(4, 0, 8, 5)}},
                                     RoofRegion{2, flat, {rect(8, 0, 9, 5)}}};
  std::vector<PlaneFit> fits(3);
  for (size_t r = 0; r < 3; ++r) fits[r].plane = roof[r].plane, fits[r].inliers = 100 + int(r), fits[r].rmse = 0.01;
  fits[0].sigma_normal = 0.01;
  const std::vector<std::vector<Face>> faces{{on_plane(rect(0, 0, 4, 5).outer, south)},
                                             {on_plane(rect(4, 0, 8, 5).outer, flat)},
                                             {}};  // region 2: no piece of it left
  std::vector<OutlineEdge> edges(4);
  const std::vector<Vec2> c{{0, 0}, {9, 0}, {9, 5}, {0, 5}};
  for (size_t i = 0; i < 4; ++i) edges[i].a = c[i], edges[i].b = c[(i + 1) % 4];
  RoofEdgeNoise noise;
  noise.noise = 0.03, noise.density = 40;
  const std::vector<Element> elements = roof_elements(roof, fits, edges, noise, faces);
  ASSERT_EQ(elements.size(), 2u);
  EXPECT_EQ(elements[0].type, ElementType::Roof);
  EXPECT_NEAR(elements[0].slope_deg, 45, 1e-9);
  EXPECT_NEAR(elements[0].azimuth_deg, 180, 1e-9);
  EXPECT_EQ(elements[0].support_points, 100);
  EXPECT_NEAR(elements[0].area, 20 * std::sqrt(2.0), 1e-9);
  // Flat: only its outline edges count (4 m of the south and north edges, the
  // 5 m west one is region 2's neighbour's, not the outline's), each on its
  // own plus the shift the roof's outline shares (24 of its 28 m read).
  const double own2 = 2 * std::pow(4 * noise.edge(9), 2), shared = 8 * noise.common(24);
  EXPECT_NEAR(elements[1].sigma_area, std::sqrt(own2 + shared * shared), 1e-12);
  EXPECT_NEAR(elements[1].sigma_shared, shared, 1e-12);
  // Region 0 reaches the west edge too; lifted by 1 / cos 45, and the tilt.
  const double own2_0 = 2 * std::pow(4 * noise.edge(9), 2) + std::pow(5 * noise.edge(5), 2);
  const double tilt = 20 * std::sqrt(2.0) * 1 * 0.01, shared0 = std::sqrt(2.0) * 13 * noise.common(24);
  EXPECT_NEAR(elements[0].sigma_area, std::sqrt(2 * own2_0 + tilt * tilt + shared0 * shared0), 1e-9);
}

TEST(EnvelopeElements, GroundAndOuterCeilingUncertainties) {
  const Face ground{{{0, 0, 0}, {0, 8, 0}, {10, 8, 0}, {10, 0, 0}}, {}};
  SharedSigma walls;
  walls.add(1.2, 0.9);
  const Element g = ground_element(ground, walls);
  EXPECT_EQ(g.type, ElementType::Ground);
  EXPECT_NEAR(g.area, 80, 1e-9);
  EXPECT_NEAR(g.sigma_area, 1.5, 1e-12);
  EXPECT_NEAR(g.sigma_shared, 0.9, 1e-12);
  const Element oc = outer_ceiling({ground}, walls);
  EXPECT_EQ(oc.type, ElementType::OuterCeiling);
  EXPECT_NEAR(oc.sigma_area, 1.5, 1e-12);
}
