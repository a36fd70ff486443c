#pragma once
// Dense path of `cadastre3d optimize`: mesh / point I/O, preprocessing (voxel,
// statistical and radius outlier removal, in XY tiles for big clouds), RANSAC
// planes, greedy-projection meshing, triangle-to-plane assignment, optimizer.
#include <string>
#include <vector>

#include "core/optimizer/optimizer.h"

namespace c3d {

struct DenseOptions {
  double voxel_m = 0.05;
  int sor_neighbours = 12;
  double sor_std = 2.5;
  double ror_radius_m = 0.3;
  int ror_min_neighbours = 3;
  double tile_m = 40.0;              // preprocessing / meshing tile size in XY
  double ransac_threshold_m = 0.05;
  int min_plane_points = 200;
  int max_planes = 30;
  double greedy_radius_m = 0.6;      // GreedyProjectionTriangulation search radius
  double assign_distance_m = 0.2;    // triangle -> plane: centroid distance
  double assign_angle_deg = 45;      // and normal angle
  OptimizerOptions optimizer;
};

struct DenseReport {
  std::size_t input_points = 0, kept_points = 0, triangles = 0;
  int tiles = 0, planes = 0, constrained_triangles = 0;
  double deviation_before = 0, deviation_after = 0;  // mean point-to-mesh distance, m
  OptimizeReport optimizer;
};

// PLY (ascii/binary, float or double) and OBJ meshes; PLY points. World coordinates.
TriMesh read_mesh(const std::string& path);
std::vector<Vec3> read_points(const std::string& path);
void write_mesh_ply(const std::string& path, const TriMesh& mesh);

std::vector<Vec3> preprocess_points(const std::vector<Vec3>& points, const DenseOptions& o, int* tiles = nullptr);
std::vector<PrimitivePlane> detect_planes(const std::vector<Vec3>& points, const DenseOptions& o);
TriMesh greedy_mesh(const std::vector<Vec3>& points, const DenseOptions& o);

// Everything in local coordinates. An empty mesh is built from the points.
DenseReport optimize_dense(TriMesh& mesh, const std::vector<Vec3>& points, const DenseOptions& o);

}  // namespace c3d
