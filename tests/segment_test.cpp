// Stage "segment": planar roof components from the points.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <set>
#include <random>

#include "core/config/config.h"
#include "core/reconstruct/envelope/envelope.h"
#include "core/evaluate/evaluate.h"
#include "core/geometry/geometry.h"
#include "core/reconstruct/outline/outline.h"
#include "core/reconstruct/planes/planes.h"
#include "core/reconstruct/ownership/ownership.h"
#include "core/reconstruct/reconstruct.h"
#include "core/reconstruct/roof/roof.h"
#include "core/synthetic/sample_town.h"
#include "core/geometry/polygon_ops.h"
#include "core/reconstruct/segment/segmentation.h"
#include "core/check/solid_check.h"
#include "ifc_citygml/validate.h"
#include "tests/test_support.h"
#include "tests/reconstruct_fixtures.h"

using namespace c3d;
using namespace c3d::test;

TEST(Segmentation, CorrugatedSlopeBecomesOnePlane) {
  // A gable at the Cimahi UAV density (87 points/m2, 1 cm noise): the south
  // slope smooth, the north slope corrugated sheet (5 cm waves every 0.35 m
  // along the eave: the sheet tilts by up to 42 degrees). Region growing alone
  // kept 75 % of the sheet's points in its plane; each slope must come out as
  // one plane holding nearly all of its points.
  std::mt19937_64 rng(7);
  Plane south = plane_through({0, 0, 5}, {0, -0.47, 1}), north = plane_through({0, 0, 5}, {0, 0.47, 1});
  auto pts = sample_plane(south, 0, 10, -4, 0, 87, 0.01, rng);
  const size_t south_points = pts.size();
  for (Vec3 q : sample_plane(north, 0, 10, 0, 4, 87, 0.01, rng)) {
    q.z() += 0.05 * std::sin(2 * M_PI * q.x() / 0.35);
    pts.push_back(q);
  }
  ReconstructionParams p;
  Segmentation seg = segment_roofs(pts, p);
  ASSERT_EQ(seg.components.size(), 2u);
  for (const auto& c : seg.components) {
    const bool is_north = c.fit.centroid.y() > 0;
    const double expected = double(is_north ? pts.size() - south_points : south_points);
    EXPECT_GT(double(c.points.size()), 0.93 * expected) << (is_north ? "north" : "south");
    EXPECT_NEAR(c.fit.plane.n.y() / c.fit.plane.n.z(), is_north ? 0.47 : -0.47, 0.02);
  }
}
