// Merging coplanar roof components: the same merges as testing every pair
// again after each merge, with far fewer tests.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/reconstruct/planes/planes.h"
#include "core/reconstruct/segment/coplanar.h"

using namespace c3d;

namespace {

// The plain rule: after every merge, test all pairs again from the first.
void merge_by_rescanning(const std::vector<Vec3>& pts, std::vector<RoofComponent>& comps, double tol) {
  for (bool merged = true; merged;) {
    merged = false;
    for (size_t i = 0; i < comps.size() && !merged; ++i)
      for (size_t j = i + 1; j < comps.size() && !merged; ++j) {
        const PlaneFit &a = comps[i].fit, &b = comps[j].fit;
        const double deg = std::acos(std::min(1.0, std::abs(a.plane.n.dot(b.plane.n)))) * 180.0 / M_PI;
        if (deg > 6.0 || std::abs(a.plane.distance(b.centroid)) > tol ||
            std::abs(b.plane.distance(a.centroid)) > tol)
          continue;
        comps[i].points.insert(comps[i].points.end(), comps[j].points.begin(), comps[j].points.end());
        comps[i].fit = fit_plane_robust(pts, comps[i].points, tol);
        comps.erase(comps.begin() + long(j));
        merged = true;
      }
  }
}

// Patches of 30 points each on one of four roof planes (two of them 2 degrees
// apart, one 0.3 m above another), shuffled.
std::vector<RoofComponent> patches(std::vector<Vec3>& pts, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0, 1), noise(-0.01, 0.01);
  const auto z = [](int plane, double x, double y) {
    switch (plane) {
      case 0: return 5.0 + 0.5 * x;
      case 1: return 5.0 + std::tan(atan(0.5) + 2 * M_PI / 180) * x;
      case 2: return 8.0 - 0.4 * y;
      default: return 5.3 + 0.5 * x;
    }
  };
  std::vector<RoofComponent> comps;
  for (int c = 0; c < 60; ++c) {
    const int plane = int(rng() % 4);
    const double x0 = 8 * u(rng), y0 = 8 * u(rng);
    RoofComponent comp;
    for (int k = 0; k < 30; ++k) {
      const double x = x0 + 2 * u(rng), y = y0 + 2 * u(rng);
      comp.points.push_back(int(pts.size()));
      pts.emplace_back(x, y, z(plane, x, y) + noise(rng));
    }
    comp.fit = fit_plane_robust(pts, comp.points, 0.1);
    comps.push_back(std::move(comp));
  }
  return comps;
}

}  // namespace

TEST(Coplanar, SameMergesAsRescanningEveryPair) {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    std::mt19937 rng(seed);
    std::vector<Vec3> pts;
    std::vector<RoofComponent> fast = patches(pts, rng), plain = fast;
    merge_coplanar(pts, fast, 0.1);
    merge_by_rescanning(pts, plain, 0.1);
    ASSERT_EQ(fast.size(), plain.size()) << "seed " << seed;
    EXPECT_LT(fast.size(), 60u);  // some patches did merge
    EXPECT_GE(fast.size(), 3u);   // the 0.3 m step and the 40 % plane stay apart
    for (size_t i = 0; i < fast.size(); ++i) {
      EXPECT_EQ(fast[i].points, plain[i].points) << "seed " << seed << " component " << i;
      EXPECT_EQ(fast[i].fit.centroid, plain[i].fit.centroid);
    }
  }
}
