// Envelope sub-stage "wall faces" alone: the wall under a footprint edge up
// to the roof underside, step walls between roof pieces, the facade elements
// (party walls among them) and the sliver step walls folded into a wall.

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/geometry/geometry.h"
#include "core/reconstruct/envelope/envelope.h"
#include "core/reconstruct/envelope/wall_faces.h"

using namespace c3d;
using namespace c3d::envelope;

namespace {

// The inside roof piece over [x0,x1] x [y0,y1] at z(x, y), counter-clockwise.
template <class Z>
Face piece(double x0, double y0, double x1, double y1, Z z) {
  Face f;
  for (const Vec2& p : {Vec2(x0, y0), Vec2(x1, y0), Vec2(x1, y1), Vec2(x0, y1)})
    f.ring.emplace_back(p.x(), p.y(), z(p.x(), p.y()));
  return f;
}
auto at(double z) {
  return [z](double, double) { return z; };
}

double total_area(const std::vector<Face>& faces) {
  double a = 0;
  for (const Face& f : faces) a += area(f);
  return a;
}

// The edges of the rectangle [x0,x1] x [y0,y1], counter-clockwise from its
// south-west corner, each with `overhang` and `sigma`.
std::vector<OutlineEdge> rect_edges(double x0, double y0, double x1, double y1, double overhang, double sigma) {
  const std::vector<Vec2> c{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
  std::vector<OutlineEdge> edges(4);
  for (size_t i = 0; i < 4; ++i) {
    edges[i].a = c[i];
    edges[i].b = c[(i + 1) % 4];
    edges[i].overhang = overhang;
    edges[i].sigma = sigma;
    edges[i].evidence = WallEvidence::Measured;
  }
  return edges;
}

}  // namespace

TEST(EnvelopeWallFaces, WallUnderAFlatRoofIsARectangleFacingOut) {
  const Face w = wall_under({0, 0}, {10, 0}, 0, {piece(0, 0, 10, 10, at(3))});
  ASSERT_EQ(w.ring.size(), 4u);
  EXPECT_NEAR(area(w), 30, 1e-9);
  EXPECT_NEAR(unit_normal(w).y(), -1, 1e-12);  // south, out of the footprint
}

TEST(EnvelopeWallFaces, WallFollowsTheRoofUndersideAlongTheEdge) {
  // Under a slope z = 3 + 0.2 x: a trapezoid.
  const Face slope = wall_under({0, 0}, {10, 0}, 0, {piece(0, 0, 10, 10, [](double x, double) { return 3 + 0.2 * x; })});
  EXPECT_NEAR(area(slope), 10 * (3 + 5) / 2.0, 1e-9);
  // Under two flat pieces at 3 and 5 m: a step at x = 5.
  const Face step = wall_under({0, 0}, {10, 0}, 0, {piece(0, 0, 5, 10, at(3)), piece(5, 0, 10, 10, at(5))});
  EXPECT_NEAR(area(step), 5 * 3 + 5 * 5, 1e-9);
  int at_step = 0;
  for (const Vec3& p : step.ring) at_step += p.x() == 5 && (p.z() == 3 || p.z() == 5);
  EXPECT_EQ(at_step, 2);
}

TEST(EnvelopeWallFaces, NoWallWhereNoPieceLiesOnTheEdge) {
  EXPECT_TRUE(wall_under({0, 20}, {10, 20}, 0, {piece(0, 0, 10, 10, at(3))}).ring.empty());
}

TEST(EnvelopeWallFaces, ARoofBelowTheTerrainDoesNotFoldTheWall) {
  const Face w = wall_under({0, 0}, {10, 0}, 4, {piece(0, 0, 10, 10, at(3))});
  for (const Vec3& p : w.ring) EXPECT_GE(p.z(), 4);
  EXPECT_NEAR(area(w), 10 * 0.01, 1e-9);
}

TEST(EnvelopeWallFaces, StepWallBetweenTwoLevelsUnderTheHigherRegion) {
  const auto steps = step_walls({piece(0, 0, 5, 10, at(3)), piece(5, 0, 10, 10, at(5))}, {7, 8});
  ASSERT_EQ(steps.size(), 1u);
  ASSERT_EQ(steps.count(8), 1u);  // the higher piece's region
  EXPECT_NEAR(total_area(steps.at(8)), 10 * 2, 1e-9);
  EXPECT_NEAR(unit_normal(steps.at(8)[0]).x(), -1, 1e-12);  // facing the lower roof
  EXPECT_TRUE(step_walls({piece(0, 0, 5, 10, at(3)), piece(5, 0, 10, 10, at(3))}, {7, 8}).empty());
}

TEST(EnvelopeWallFaces, CrossingRoofsEachWallTheirHigherPart) {
  // West z = 3 + 0.2 y, east z = 4: they cross at y = 5 on the shared edge.
  const auto steps = step_walls(
      {piece(0, 0, 5, 10, [](double, double y) { return 3 + 0.2 * y; }), piece(5, 0, 10, 10, at(4))}, {0, 1});
  ASSERT_EQ(steps.size(), 2u);
  EXPECT_NEAR(total_area(steps.at(0)), 0.5 * 5 * 1, 1e-9);
  EXPECT_NEAR(total_area(steps.at(1)), 0.5 * 5 * 1, 1e-9);
}

TEST(EnvelopeWallFaces, SourceEdgeIsTheParallelNearestOutlineEdge) {
  const std::vector<OutlineEdge> edges = rect_edges(0, 0, 12, 10, 1, 0.1);
  EXPECT_EQ(&source_edge(edges, {1, 1}, {11, 1}), &edges[0]);
  EXPECT_EQ(&source_edge(edges, {11, 1}, {11, 9}), &edges[1]);
  EXPECT_EQ(&source_edge(edges, {4, 9}, {1, 9}), &edges[2]);  // a part of the north wall
}

TEST(EnvelopeWallFaces, FacadesOnePerOutlineEdgeWithTheirEvidence) {
  std::vector<OutlineEdge> edges = rect_edges(0, 0, 12, 10, 1, 0.1);
  edges[1].party = true;
  edges[1].evidence = WallEvidence::ParcelBoundary;
  // The footprint ring starts in the middle of the south wall: its two
  // pieces are one element. The roof piece is noded with it (simple_pieces).
  const Polygon2 fp{{{6, 1}, {11, 1}, {11, 9}, {1, 9}, {1, 1}}, {}};
  const Face roof{{{1, 1, 3}, {6, 1, 3}, {11, 1, 3}, {11, 9, 3}, {1, 9, 3}}, {}};
  const Facades f = facade_walls(fp, edges, 0, {roof}, RoofEdgeNoise{});
  EXPECT_EQ(f.faces.size(), 5u);
  ASSERT_EQ(f.elements.size(), 4u);
  double walls = 0, party = 0;
  for (const Element& e : f.elements) (e.type == ElementType::PartyWall ? party : walls) += e.area;
  EXPECT_NEAR(walls, (10 + 10 + 8) * 3.0, 1e-9);
  EXPECT_NEAR(party, 8 * 3.0, 1e-9);
  for (const Element& e : f.elements) {
    EXPECT_EQ(e.slope_deg, 90.0);
    if (e.faces.size() == 2) EXPECT_NEAR(e.azimuth_deg, 180, 1e-9);  // the south wall, both pieces
  }
  // The ground area's variance from each wall's position: (length * sigma)^2.
  EXPECT_NEAR(f.ground.own2, 5 * 5 * 0.01 + 8 * 8 * 0.01 + 10 * 10 * 0.01 + 8 * 8 * 0.01 + 5 * 5 * 0.01, 1e-12);
  EXPECT_EQ(f.ground.shared, 0.0);
}

TEST(EnvelopeWallFaces, StepWallElementsAndSliversFoldedIntoTheNearestWall) {
  const StepWalls s = step_wall_elements({piece(0, 0, 5, 10, at(3)), piece(5, 0, 10, 10, at(5))}, {0, 1});
  ASSERT_EQ(s.elements.size(), 1u);
  EXPECT_EQ(s.faces.size(), 1u);
  EXPECT_EQ(s.elements[0].evidence, WallEvidence::RoofStep);
  EXPECT_NEAR(s.elements[0].area, 20, 1e-9);
  EXPECT_NEAR(s.elements[0].sigma_area, 0.05 * std::sqrt(20.0), 1e-12);

  auto wall_at_x = [](double x) {
    Element w;
    w.type = ElementType::Wall;
    w.faces = {Face{{{x, 0, 0}, {x, 1, 0}, {x, 1, 1}, {x, 0, 1}}, {}}};
    w.area = 1;
    return w;
  };
  std::vector<Element> elements{wall_at_x(0), wall_at_x(10)};
  Element sliver;  // 0.1 x 0.05 m beside the wall at x = 10
  sliver.type = ElementType::Wall;
  sliver.faces = {Face{{{9.9, 0.5, 0}, {10, 0.5, 0}, {10, 0.5, 0.05}, {9.9, 0.5, 0.05}}, {}}};
  sliver.area = 0.005;
  Element big = sliver;  // beside the wall at x = 0
  big.faces = {Face{{{0.1, 0.5, 0}, {0.3, 0.5, 0}, {0.3, 0.5, 0.1}, {0.1, 0.5, 0.1}}, {}}};
  big.area = 0.02;
  std::vector<Element> steps{sliver, big};
  fold_sliver_steps(steps, elements);
  ASSERT_EQ(elements.size(), 3u);  // the two walls and the larger step wall
  EXPECT_EQ(elements[1].faces.size(), 2u);
  EXPECT_NEAR(elements[1].area, 1.005, 1e-12);
  EXPECT_EQ(elements[0].faces.size(), 1u);
  EXPECT_NEAR(elements[2].area, 0.02, 1e-12);
}
