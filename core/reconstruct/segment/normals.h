#pragma once
// Point normals and the scan's sampling gaps for segmentation, robust to
// points on scan rows: where a point's k nearest all lie on its own row (a
// line), they fix no normal, and its nearest neighbours say nothing of the
// gap to the next row.
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "core/reconstruct/segment/neighbours.h"

namespace c3d {

struct PointNormals {
  pcl::PointCloud<pcl::Normal>::Ptr normals;
  int neighbours = 0;  // the median neighbourhood size the normals were taken from
};

// PCL's normal of each point from its k nearest; where those lie on a line
// (scan rows), from the 2k, 4k, ... nearest, up to 8k, the first that span a
// surface.
PointNormals estimate_normals(const pcl::PointCloud<pcl::PointXYZ>::Ptr& cloud,
                              const std::shared_ptr<NeighbourTable>& table, int k);

// The widest gap the sampling leaves around a point: per point, the distance
// to its nearest neighbour in each quarter of the plan around it, the largest
// of the four; the median over (a sample of) the points with all four quarters
// filled. 0 when none has.
double sampling_gap(const pcl::PointCloud<pcl::PointXYZ>::Ptr& cloud, const NeighbourTable& table);

}  // namespace c3d
