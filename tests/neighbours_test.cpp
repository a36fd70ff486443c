// The shared neighbour table answers as the PCL k-d tree does, and the outlier
// rule read off it keeps exactly the points PCL's StatisticalOutlierRemoval keeps.
#include <gtest/gtest.h>
#include <pcl/filters/statistical_outlier_removal.h>

#include <algorithm>
#include <random>

#include "core/reconstruct/segment/neighbours.h"

namespace c3d {
namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

// A noisy 20 x 10 m roof plane at 40 pts/m² with `outliers` points scattered above it.
Cloud::Ptr roof_with_outliers(int outliers, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> ux(0, 20), uy(0, 10), uz(1, 6);
  std::normal_distribution<float> noise(0, 0.03f);
  Cloud::Ptr c(new Cloud);
  for (int i = 0; i < 8000; ++i) {
    float x = ux(rng), y = uy(rng);
    c->push_back({x, y, 5 + 0.4f * y + noise(rng)});
  }
  for (int i = 0; i < outliers; ++i) c->push_back({ux(rng), uy(rng), 10 + uz(rng)});
  return c;
}

// A Gaussian blob: density falls off smoothly, so points lie at every distance
// from the outlier threshold and any change of the rule shows.
Cloud::Ptr blob(unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> g(0, 2);
  Cloud::Ptr c(new Cloud);
  for (int i = 0; i < 5000; ++i) c->push_back({g(rng), g(rng), 0.5f * g(rng)});
  return c;
}

TEST(NeighbourTable, AnswersAsTheKdTree) {
  auto cloud = roof_with_outliers(40, 1);
  NeighbourTable table(cloud, 16);
  pcl::search::KdTree<pcl::PointXYZ> tree;
  tree.setInputCloud(cloud);
  pcl::Indices a, b;
  std::vector<float> da, db;
  for (int k : {2, 13, 16, 24}) {  // 24: more than it holds, so the tree answers
    for (pcl::index_t i = 0; i < pcl::index_t(cloud->size()); i += 97) {
      ASSERT_EQ(table.nearestKSearch(i, k, a, da), tree.nearestKSearch(i, k, b, db));
      EXPECT_EQ(a, b) << "point " << i << ", k " << k;
      EXPECT_EQ(da, db);
    }
  }
  EXPECT_THROW(table.setInputCloud(roof_with_outliers(0, 2), nullptr), std::logic_error);
}

TEST(NeighbourTable, OutlierRuleKeepsWhatPclKeeps) {
  for (unsigned seed : {3u, 4u, 5u}) {
    auto cloud = blob(seed);
    NeighbourTable table(cloud, 16);
    pcl::Indices ours = remove_statistical_outliers(table, 12, 2.5);

    pcl::StatisticalOutlierRemoval<pcl::PointXYZ> sor;
    sor.setInputCloud(cloud);
    sor.setMeanK(12);
    sor.setStddevMulThresh(2.5);
    pcl::Indices pcls;
    sor.filter(pcls);
    EXPECT_EQ(ours, pcls) << "seed " << seed;
    EXPECT_LT(ours.size(), cloud->size());
  }
}

TEST(NeighbourTable, OutlierRuleDropsPointsAboveTheRoof) {
  for (unsigned seed : {3u, 4u, 5u}) {
    auto cloud = roof_with_outliers(60, seed);
    NeighbourTable table(cloud, 16);
    pcl::Indices ours = remove_statistical_outliers(table, 12, 2.5);
    long roof_kept = std::count_if(ours.begin(), ours.end(), [](pcl::index_t i) { return i < 8000; });
    EXPECT_GT(roof_kept, 7900);
    EXPECT_LT(long(ours.size()) - roof_kept, 10) << "seed " << seed;
  }
}

}  // namespace
}  // namespace c3d
