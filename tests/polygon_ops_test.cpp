// Polygon operations the stages share (needles, land between parcels).

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

TEST(PolygonOps, NeedleTipsGoSharpCornersStay) {
  // A 10 x 8 m outline with a 0.13 m needle of almost no width at a corner
  // (as subtracting a parcel cut can leave): the tip goes, the area stays.
  // A 5 degree wedge is a real, if sharp, corner and stays.
  const MultiPolygon2 needled{{{{0, 0}, {10, 0}, {10.13, -0.0001}, {10, 0.0001}, {10, 8}, {0, 8}}, {}}};
  const MultiPolygon2 out = poly::drop_needles(needled, 0.0175);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].outer.size(), 5u);  // one tip, and the base vertex left on a straight edge stays
  EXPECT_NEAR(area(out), 80.0, 1e-3);
  for (const Vec2& v : out[0].outer) EXPECT_LE(v.x(), 10.0 + 1e-9);
  const MultiPolygon2 wedge{{{{0, 0}, {10, 0}, {0, 10 * std::tan(5 * M_PI / 180)}}, {}}};
  EXPECT_EQ(poly::drop_needles(wedge, 0.0175)[0].outer.size(), 3u);
}

TEST(PolygonOps, LandBeyondASharedCornerGoesToTheNearerParcel) {
  // Two unit parcels side by side; within 0.5 m of b (a mitred buffer), outside
  // both, the land nearer to b is all of it beyond the line of their shared
  // edge: 2 m^2.
  const MultiPolygon2 a = poly::box({0, 0}, {1, 1}), b = poly::box({1, 0}, {2, 1});
  const MultiPolygon2 land = poly::nearer_to(b, a, 0.5, 0.1);
  EXPECT_NEAR(area(land), 2.0, 1e-6);
  EXPECT_TRUE(poly::covers(land, {1.25, -0.25}));
  EXPECT_TRUE(poly::covers(land, {1.25, 1.25}));
  EXPECT_TRUE(poly::covers(land, {2.25, 0.5}));
  EXPECT_FALSE(poly::covers(land, {0.75, -0.25}));
  EXPECT_TRUE(poly::nearer_to(b, poly::box({5, 0}, {6, 1}), 0.5, 0.1).empty());  // too far apart to split land
}

TEST(PolygonOps, NearZoneFindsTheSharedBoundaryOnceBuilt) {
  // b's zone built once answers for several a: a 1 m edge shared with the
  // square next to it, a 0.5 m stretch with the one offset half a metre, and
  // nothing with one 1 cm away (beyond the 1e-4 m tolerance) or far off.
  const MultiPolygon2 b = poly::box({0, 0}, {1, 1});
  const poly::NearZone zone(b, 1e-4);
  auto length = [](const std::vector<std::vector<Vec2>>& lines) {
    double len = 0;
    for (const auto& l : lines)
      for (size_t i = 1; i < l.size(); ++i) len += (l[i] - l[i - 1]).norm();
    return len;
  };
  const MultiPolygon2 side = poly::box({1, 0}, {2, 1}), offset = poly::box({1, 0.5}, {2, 1.5});
  EXPECT_NEAR(length(zone.shared_with(side)), 1.0, 1e-3);
  EXPECT_NEAR(length(zone.shared_with(offset)), 0.5, 1e-3);
  EXPECT_TRUE(zone.shared_with(poly::box({1.01, 0}, {2, 1})).empty());
  EXPECT_TRUE(zone.shared_with(poly::box({5, 5}, {6, 6})).empty());
  // the same lines as the one-off call
  EXPECT_EQ(zone.shared_with(offset), poly::shared_boundary(offset, b, 1e-4));
}
