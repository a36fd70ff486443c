// Window and door frames through the mesh ladder (issue 50, seed 002): the
// sample town's recessed openings (SampleOptions::openings) scanned densely,
// their frames known. At the same face budgets the boundary-aware levels
// keep the frames nearer than plain QEM does.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "core/mesh/ladder.h"
#include "core/synthetic/sample_town.h"

namespace c3d {
namespace {

// One house, every wall scanned at handheld density, nothing but surfaces.
SampleTown house_with_openings() {
  SampleOptions o;
  o.parcels = 1;
  o.seed = 3;
  o.openings = true;
  o.roof_density = 40, o.wall_density = 150;  // 8 cm apart on the walls: two across a reveal
  o.wall_occlusion = 0, o.clutter_share = 0, o.outlier_share = 0, o.ground_density = 0;
  return make_sample_town(o);
}

// The building's points in the town's local frame.
std::vector<Vec3> building_points(const SampleTown& town) {
  std::vector<Vec3> out;
  for (size_t i = 0; i < town.cloud.points.size(); ++i)
    if (town.point_tags[i] == PointTag::Surface) out.push_back(town.cloud.points[i] - town.frame.origin);
  return out;
}

// Points every 2 cm along each opening's frame (where the reveal meets the
// wall) and its pane's edges: the creases a mesh must keep.
std::vector<Vec3> frame_edges(const std::vector<Opening>& openings) {
  std::vector<Vec3> out;
  for (const Opening& o : openings)
    for (const Vec3& back : {Vec3(Vec3::Zero()), Vec3(o.inward * o.depth)})
      for (size_t i = 0; i < 4; ++i) {
        const Vec3 a = o.frame[i] + back, b = o.frame[(i + 1) % 4] + back;
        const int n = std::max(1, int((b - a).norm() / 0.02));
        for (int k = 0; k < n; ++k) out.push_back(a + (b - a) * (k + 0.5) / n);
      }
  return out;
}

// Plain QEM is Garland and Heckbert's plane quadrics (seed 002's baseline).
// CGAL's Lindstrom-Turk collapse, the boundary-aware one's cost, keeps these
// frames without regions too (docs/meshes.md has its figures).
TEST(MeshFacade, BoundaryAwareLevelsKeepFramesNearerThanPlainQem) {
  const SampleTown town = house_with_openings();
  ASSERT_EQ(town.truth.size(), 1u);
  std::vector<Opening> openings;
  for (const TruthBuilding& tb : town.truth[0]) openings.insert(openings.end(), tb.openings.begin(), tb.openings.end());
  ASSERT_GE(openings.size(), 4u);
  EXPECT_EQ(std::count_if(openings.begin(), openings.end(), [](const Opening& o) { return o.kind == "door"; }),
            long(town.truth[0].size()));
  const std::vector<Vec3> points = building_points(town), edges = frame_edges(openings);
  const MeshLadder aware = mesh_ladder(points, DenseMethod::AdvancingFront);
  MeshLadder plain = aware;  // the same level 4 and the same budgets
  simplify_levels(plain, Simplifier::GarlandHeckbert, points);
  MeshLadder turk = aware;  // printed for docs/meshes.md, not held to anything
  simplify_levels(turk, Simplifier::LindstromTurk, points);
  const Spread dense = spread_of(distances_to(aware.level(4).mesh, edges));
  EXPECT_LT(dense.mean, 0.03);  // level 4 follows the frames within the noise and the spacing
  for (int k : {3, 2}) {
    const Spread kept = spread_of(distances_to(aware.level(k).mesh, edges));
    const Spread smeared = spread_of(distances_to(plain.level(k).mesh, edges));
    const Spread turked = spread_of(distances_to(turk.level(k).mesh, edges));
    std::printf("level %d: frames' distance mean / p95 %.4f / %.4f m boundary-aware (%zu faces), %.4f / %.4f m "
                "plain QEM (%zu faces), %.4f / %.4f m Lindstrom-Turk (%zu faces); level 4 %.4f / %.4f m (%zu faces)\n",
                k, kept.mean, kept.p95, aware.level(k).metrics.faces, smeared.mean, smeared.p95,
                plain.level(k).metrics.faces, turked.mean, turked.p95, turk.level(k).metrics.faces, dense.mean,
                dense.p95, aware.level(4).metrics.faces);
    EXPECT_LT(kept.mean, smeared.mean) << "level " << k;
    EXPECT_LT(kept.p95, smeared.p95) << "level " << k;
    EXPECT_LE(aware.level(k).metrics.faces, plain.level(k).metrics.faces * 21 / 20) << "level " << k;
  }
}

}  // namespace
}  // namespace c3d
