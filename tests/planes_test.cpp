// Stage "planes": robust plane fits, ridge lines and three-plane points.

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

TEST(Planes, SvdFitRecoversNoisyPlane) {
  std::mt19937_64 rng(3);
  Plane truth = plane_through({0, 0, 5}, {0.3, -0.2, 1});
  auto pts = sample_plane(truth, 0, 10, 0, 8, 40, 0.03, rng);
  PlaneFit f = fit_plane(pts);
  EXPECT_LT(std::acos(std::min(1.0, f.plane.n.dot(truth.n))), 0.005);
  EXPECT_NEAR(f.plane.z_at(5, 4), truth.z_at(5, 4), 0.01);
  EXPECT_NEAR(f.rmse, 0.03 * std::sqrt(1 + 0.3 * 0.3 + 0.2 * 0.2) / std::sqrt(1.13), 0.01);
  EXPECT_GT(f.sigma_normal, 0.0);
}

TEST(Planes, RobustFitIgnoresClutter) {
  std::mt19937_64 rng(4);
  Plane truth = plane_through({0, 0, 3}, {0, 0.5, 1});
  auto pts = sample_plane(truth, 0, 10, 0, 10, 30, 0.02, rng);
  for (int i = 0; i < 200; ++i) pts.emplace_back(5 + 0.01 * i, 5, 12.0);  // an antenna
  PlaneFit f = fit_plane_robust(pts, {}, 0.15);
  EXPECT_NEAR(f.plane.z_at(2, 2), truth.z_at(2, 2), 0.01);
  EXPECT_LE(f.inliers, int(pts.size()) - 200);
}

TEST(Planes, RidgeAndThreePlanePoint) {
  Plane a = plane_through({0, 5, 10}, {0, -0.6, 1});  // falls toward -y
  Plane b = plane_through({0, 5, 10}, {0, 0.6, 1});   // falls toward +y
  auto ridge = intersect(a, b);
  ASSERT_TRUE(ridge);
  EXPECT_NEAR(ridge->point.y(), 5.0, 1e-9);
  EXPECT_NEAR(ridge->point.z(), 10.0, 1e-9);
  EXPECT_NEAR(std::abs(ridge->dir.x()), 1.0, 1e-9);
  EXPECT_FALSE(intersect(a, a));  // parallel: no line
  Plane hip = plane_through({10, 5, 10}, {0.6, 0, 1});
  auto p = common_point({a, b, hip});
  ASSERT_TRUE(p);
  EXPECT_NEAR((*p - Vec3(10, 5, 10)).norm(), 0.0, 1e-9);
}
