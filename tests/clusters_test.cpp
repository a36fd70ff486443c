// The grid clustering gives what pcl::EuclideanClusterExtraction gives: the
// same clusters in the same order, on clouds where near and far pairs lie
// close to the tolerance.
#include <gtest/gtest.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/extract_clusters.h>

#include <numeric>
#include <random>
#include <stdexcept>

#include "core/reconstruct/segment/clusters.h"

namespace c3d {
namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

std::vector<pcl::PointIndices> pcl_clusters(const Cloud::Ptr& cloud, const pcl::Indices& indices, float tol,
                                            int min_points) {
  pcl::EuclideanClusterExtraction<pcl::PointXYZ> ec;
  ec.setClusterTolerance(tol);
  ec.setMinClusterSize(min_points);
  ec.setMaxClusterSize(std::numeric_limits<int>::max());
  ec.setSearchMethod(pcl::search::KdTree<pcl::PointXYZ>::Ptr(new pcl::search::KdTree<pcl::PointXYZ>(false)));
  ec.setInputCloud(cloud);
  ec.setIndices(pcl::make_shared<pcl::Indices>(indices));
  std::vector<pcl::PointIndices> out;
  ec.extract(out);
  return out;
}

// Roofs of 40 pts/m² as boxes of points, some apart by gaps around the
// tolerance, with loose points between them and one dense clump.
Cloud::Ptr town(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0, 1);
  Cloud::Ptr c(new Cloud);
  for (int roof = 0; roof < 12; ++roof) {
    const float x0 = float(roof % 4) * 10.5f + u(rng), y0 = float(roof / 4) * 8.4f + u(rng);
    const float w = 6 + 3 * u(rng), d = 5 + 2 * u(rng), h = 3 + 6 * u(rng);
    for (int i = 0; i < int(40 * w * d); ++i) c->push_back({x0 + w * u(rng), y0 + d * u(rng), h + 0.5f * u(rng)});
  }
  for (int i = 0; i < 300; ++i) c->push_back({44 * u(rng), 26 * u(rng), 12 * u(rng)});
  for (int i = 0; i < 2000; ++i) c->push_back({20 + 0.3f * u(rng), 30 + 0.3f * u(rng), 2 + 0.2f * u(rng)});
  return c;
}

void expect_same(const std::vector<pcl::PointIndices>& want, const std::vector<pcl::PointIndices>& got) {
  ASSERT_EQ(want.size(), got.size());
  for (size_t i = 0; i < want.size(); ++i) EXPECT_EQ(want[i].indices, got[i].indices) << "cluster " << i;
}

TEST(Clusters, SameAsPclOnRoofsApartByAboutTheTolerance) {
  for (unsigned seed : {1u, 2u, 3u}) {
    const Cloud::Ptr cloud = town(seed);
    pcl::Indices every(cloud->size());
    std::iota(every.begin(), every.end(), 0);
    for (float tol : {0.3f, 0.5f, 1.2f}) {
      const auto want = pcl_clusters(cloud, every, tol, 5);
      ASSERT_GT(want.size(), 3u);
      expect_same(want, euclidean_clusters(*cloud, every, tol, 5, std::numeric_limits<int>::max()));
    }
  }
}

TEST(Clusters, SameAsPclOnSomeOfThePoints) {
  const Cloud::Ptr cloud = town(7);
  pcl::Indices some;
  for (int i = 0; i < int(cloud->size()); i += 3) some.push_back(i);
  const auto want = pcl_clusters(cloud, some, 0.6f, 1);
  expect_same(want, euclidean_clusters(*cloud, some, 0.6f, 1, std::numeric_limits<int>::max()));
}

// Pairs at exactly the tolerance are apart (PCL's strict test); a hair
// under, together.
TEST(Clusters, AtTheToleranceApartJustUnderTogether) {
  Cloud::Ptr cloud(new Cloud);
  cloud->push_back({0, 0, 0});
  cloud->push_back({0.5f, 0, 0});      // exactly the tolerance from the first
  cloud->push_back({0.5f, 0.49f, 0});  // under it from the second
  pcl::Indices every{0, 1, 2};
  const auto got = euclidean_clusters(*cloud, every, 0.5f, 1, 10);
  expect_same(pcl_clusters(cloud, every, 0.5f, 1), got);
  ASSERT_EQ(got.size(), 2u);
  EXPECT_EQ(got[0].indices, (pcl::Indices{1, 2}));
  EXPECT_EQ(got[1].indices, (pcl::Indices{0}));
}

// No tolerance is no clustering: said, not a division by zero.
TEST(Clusters, ToleranceMustBePositive) {
  const Cloud::Ptr cloud = town(1);
  const pcl::Indices some{0, 1, 2};
  EXPECT_THROW(euclidean_clusters(*cloud, some, 0.f, 1, 10), std::invalid_argument);
  EXPECT_THROW(euclidean_clusters(*cloud, some, -0.5f, 1, 10), std::invalid_argument);
}

}  // namespace
}  // namespace c3d
