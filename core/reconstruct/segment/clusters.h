#pragma once
// Euclidean clustering (points joined where two lie closer than a tolerance)
// on a grid of cells: pcl::EuclideanClusterExtraction lists every point's
// neighbours within the tolerance, so its time grows with the density
// squared; here the points of one cell (a diagonal under the tolerance) are
// joined at once and two cells by their first close pair.
#include <pcl/PointIndices.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <vector>

namespace c3d {

// The clusters pcl::EuclideanClusterExtraction gives for `indices` of `cloud`
// with this tolerance and these sizes: the same points, each cluster's
// indices ascending, the clusters largest first in PCL's own order. Two points
// are near as PCL's k-d tree judges them: squared float distance below the
// float square of the tolerance, which must be positive.
std::vector<pcl::PointIndices> euclidean_clusters(const pcl::PointCloud<pcl::PointXYZ>& cloud,
                                                  const pcl::Indices& indices, float tolerance,
                                                  size_t min_points, size_t max_points);

}  // namespace c3d
