#pragma once
// The k nearest neighbours of every point of one cloud, searched once with a
// PCL k-d tree and served to every step of segmentation that needs them (the
// outlier filter, PCL's normal estimation, the spacing estimate), which would
// otherwise each search the same cloud again. It is a pcl::search::Search, so
// PCL's algorithms take it as their search method; queries it does not hold
// (other points, a larger k, a radius) go to the tree.
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>

#include <vector>

namespace c3d {

class NeighbourTable : public pcl::search::Search<pcl::PointXYZ> {
 public:
  NeighbourTable(const PointCloudConstPtr& cloud, int k);

  void setInputCloud(const PointCloudConstPtr& cloud, const IndicesConstPtr& indices) override;
  int nearestKSearch(pcl::index_t index, int k, pcl::Indices& nn, std::vector<float>& d2) const override;
  int nearestKSearch(const PointCloud& cloud, pcl::index_t index, int k, pcl::Indices& nn,
                     std::vector<float>& d2) const override;
  int nearestKSearch(const pcl::PointXYZ& p, int k, pcl::Indices& nn, std::vector<float>& d2) const override;
  int radiusSearch(const pcl::PointXYZ& p, double r, pcl::Indices& nn, std::vector<float>& d2,
                   unsigned int max_nn) const override;

 private:
  pcl::search::KdTree<pcl::PointXYZ> tree_;
  int stored_ = 0;                 // neighbours stored per point: min(k, cloud size)
  std::vector<pcl::index_t> nn_;   // point i's neighbours at [i * stored_, (i + 1) * stored_), nearest first
  std::vector<float> d2_;          // their squared distances
};

// PCL's statistical outlier removal rule read off the table: a point goes when
// its mean distance to its k nearest neighbours lies more than `std_mul`
// standard deviations above the mean over all points. Returns the points kept.
// (pcl::StatisticalOutlierRemoval keeps its search object private and would
// search the cloud once more; a test holds this to its result.)
pcl::Indices remove_statistical_outliers(const NeighbourTable& table, int k, double std_mul);

}  // namespace c3d
