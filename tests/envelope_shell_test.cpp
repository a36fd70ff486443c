// Envelope sub-stage "shell" alone: welding closes a box whose corners miss
// each other by fractions of a millimetre, noding puts a vertex into the edge
// it lies on, and the elements end up with the shell's own faces.

#include <gtest/gtest.h>

#include <vector>

#include "core/check/solid_check.h"
#include "core/geometry/geometry.h"
#include "core/reconstruct/envelope/shell.h"
#include "tests/test_support.h"

using namespace c3d;
using namespace c3d::envelope;
using namespace c3d::test;

namespace {

// The 10 x 8 x 3 m box with one corner of its top face 0.4 mm off the others'.
std::vector<Face> box_with_a_missed_corner() {
  std::vector<Face> box = box_shell({0, 0, 0}, {10, 8, 3});
  box[1].ring[0] += Vec3(0.0003, -0.0002, 0.0002);  // the top's corner (0, 0, 3)
  return box;
}

bool has_vertex(const Ring3& r, const Vec3& p) {
  for (const Vec3& v : r)
    if ((v - p).norm() < 1e-12) return true;
  return false;
}

}  // namespace

TEST(EnvelopeShell, WeldingClosesABoxWhoseCornersMissByLessThanAMillimetre) {
  std::vector<Face> box = box_with_a_missed_corner();
  EXPECT_FALSE(check_solid(box).ok);  // open along the top's two edges at that corner
  Welder<Vec3> seen(1e-3);
  weld_faces(box, seen, true);
  const SolidCheck check = check_solid(box);
  EXPECT_TRUE(check.ok) << check.summary();
  EXPECT_NEAR(check.volume, 240, 0.01);
  EXPECT_EQ(seen.seen().size(), 8u);  // the box's eight corners, each once
}

TEST(EnvelopeShell, WeldingDropsAFaceLeftALine) {
  std::vector<Face> faces = box_shell({0, 0, 0}, {10, 8, 3});
  const Face speck{{{0, 0, 3}, {0.0004, 0, 3}, {0, 0.0003, 3.0002}}, {}};  // within a millimetre of a corner
  faces.push_back(speck);
  Welder<Vec3> seen(1e-3);
  weld_faces(faces, seen, true);
  EXPECT_EQ(faces.size(), 6u);
  std::vector<Face> kept = box_shell({0, 0, 0}, {10, 8, 3});
  kept.push_back(speck);
  Welder<Vec3> keep_seen(1e-3);
  weld_faces(kept, keep_seen, false);
  ASSERT_EQ(kept.size(), 7u);  // left to the caller
  EXPECT_EQ(kept[6].ring.size(), 1u);
}

TEST(EnvelopeShell, NodingPutsAVertexIntoTheEdgeItLiesOn) {
  // The top of the box split in two at x = 4: the long sides' top edges gain
  // the split's ends.
  std::vector<Face> box = box_shell({0, 0, 0}, {10, 8, 3});
  box[1] = Face{{{0, 0, 3}, {4, 0, 3}, {4, 8, 3}, {0, 8, 3}}, {}};
  box.push_back(Face{{{4, 0, 3}, {10, 0, 3}, {10, 8, 3}, {4, 8, 3}}, {}});
  EXPECT_FALSE(has_vertex(box[2].ring, {4, 0, 3}));
  const std::vector<Vec3> verts = shell_vertices(box);
  node_faces(box, EdgeNoder<Vec3>(verts, 1e-3));
  EXPECT_TRUE(has_vertex(box[2].ring, {4, 0, 3}));  // the south wall
  EXPECT_TRUE(has_vertex(box[3].ring, {4, 8, 3}));  // the north wall
  EXPECT_EQ(box[4].ring.size(), 4u);                // the west wall: nothing on it
  EXPECT_TRUE(check_solid(box).ok) << check_solid(box).summary();
}

TEST(EnvelopeShell, WeldShellGivesTheElementsTheShellsVerticesAndDropsEmptyOnes) {
  std::vector<Face> solid = box_with_a_missed_corner();
  Element roof;
  roof.type = ElementType::Roof;
  roof.faces = {solid[1]};
  Element ceiling;  // a soffit with its corner at the missed one, 0.2 mm higher
  ceiling.type = ElementType::OuterCeiling;
  ceiling.faces = {Face{{{0, 0, 3}, {0, -1, 3}, {-1, -1, 3}, {-1, 0, 3}}, {}}};
  Element line;  // a step wall sliver the weld makes a line
  line.type = ElementType::Wall;
  line.faces = {Face{{{0, 0, 0}, {0.0002, 0, 0}, {0.0002, 0, 0.0003}}, {}}};
  std::vector<Element> elements{roof, ceiling, line};
  weld_shell(solid, elements);
  EXPECT_TRUE(check_solid(solid).ok) << check_solid(solid).summary();
  ASSERT_EQ(elements.size(), 2u);  // the line went
  EXPECT_EQ(elements[0].faces[0].ring, solid[1].ring);
  for (const Vec3& p : elements[1].faces[0].ring) EXPECT_EQ(p.z(), 3);  // stays level
}
