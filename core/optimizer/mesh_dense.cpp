// Dense optimize path on PCL: filters, SAC plane segmentation, greedy projection.
#include "core/optimizer/mesh_dense.h"

#include <pcl/features/normal_3d.h>
#include <pcl/filters/extract_indices.h>
#include <pcl/filters/radius_outlier_removal.h>
#include <pcl/filters/statistical_outlier_removal.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/io/obj_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/sac_segmentation.h>
#include <pcl/surface/gp3.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <map>

#include "core/error.h"
#include "core/io/mesh_io.h"

namespace c3d {
namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

Cloud::Ptr to_pcl(const std::vector<Vec3>& pts) {
  Cloud::Ptr c(new Cloud);
  c->reserve(pts.size());
  for (const Vec3& p : pts) c->push_back(pcl::PointXYZ(float(p.x()), float(p.y()), float(p.z())));
  return c;
}

// x, y, z of a PCLPointCloud2 in double, whatever the stored type.
std::vector<Vec3> xyz_of(const pcl::PCLPointCloud2& c, const std::string& path) {
  const pcl::PCLPointField* f[3] = {nullptr, nullptr, nullptr};
  for (const auto& field : c.fields)
    for (int k = 0; k < 3; ++k)
      if (field.name == std::string(1, "xyz"[k])) f[k] = &field;
  if (!f[0] || !f[1] || !f[2]) throw InputError(path, "no x/y/z properties");
  std::vector<Vec3> out(std::size_t(c.width) * c.height);
  for (std::size_t i = 0; i < out.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const std::uint8_t* p = &c.data[i * c.point_step + f[k]->offset];
      if (f[k]->datatype == pcl::PCLPointField::FLOAT64) {
        double v;
        std::memcpy(&v, p, 8);
        out[i][k] = v;
      } else {
        float v;
        std::memcpy(&v, p, 4);
        out[i][k] = v;
      }
    }
  return out;
}

}  // namespace

TriMesh read_mesh(const std::string& path) {
  pcl::PolygonMesh pm;
  const std::string ext = lower_ext(path);
  int rc = ext == "ply" ? pcl::io::loadPLYFile(path, pm)
         : ext == "obj" ? pcl::io::loadOBJFile(path, pm)
                        : throw InputError(path, "mesh must be .ply or .obj");
  if (rc < 0) throw InputError(path, "cannot read mesh");
  TriMesh m;
  m.vertices = xyz_of(pm.cloud, path);
  for (const auto& poly : pm.polygons)  // polygons fanned into triangles
    for (std::size_t k = 1; k + 1 < poly.vertices.size(); ++k)
      m.triangles.push_back({int(poly.vertices[0]), int(poly.vertices[k]), int(poly.vertices[k + 1])});
  if (m.triangles.empty()) throw InputError(path, "mesh has no faces");
  return m;
}

std::vector<Vec3> read_points(const std::string& path) {
  if (lower_ext(path) != "ply") throw InputError(path, "points must be a .ply file");
  pcl::PCLPointCloud2 c;
  if (pcl::io::loadPLYFile(path, c) < 0) throw InputError(path, "cannot read points");
  return xyz_of(c, path);
}

void write_mesh_ply(const std::string& path, const TriMesh& m) {
  std::ofstream out(path);
  if (!out) throw InputError(path, "cannot write");
  out << "ply\nformat ascii 1.0\nelement vertex " << m.vertices.size()
      << "\nproperty double x\nproperty double y\nproperty double z\nelement face "
      << m.triangles.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
  out.precision(12);
  for (const Vec3& p : m.vertices) out << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  for (const auto& t : m.triangles) out << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
}

// Filters run per XY tile so that the peak memory of PCL's kd-trees stays
// bounded for clouds of many millions of points.
std::vector<Vec3> preprocess_points(const std::vector<Vec3>& points, const DenseOptions& o, int* tiles) {
  std::map<std::pair<long, long>, std::vector<Vec3>> tile;
  for (const Vec3& p : points)
    tile[{std::lround(std::floor(p.x() / o.tile_m)), std::lround(std::floor(p.y() / o.tile_m))}].push_back(p);
  if (tiles) *tiles = static_cast<int>(tile.size());
  std::vector<Vec3> out;
  for (auto& [key, pts] : tile) {
    Cloud::Ptr c = to_pcl(pts);
    std::vector<Vec3>().swap(pts);
    if (o.voxel_m > 0) {
      Cloud::Ptr v(new Cloud);
      pcl::VoxelGrid<pcl::PointXYZ> vg;
      vg.setInputCloud(c);
      vg.setLeafSize(float(o.voxel_m), float(o.voxel_m), float(o.voxel_m));
      vg.filter(*v);
      c = v;
    }
    if (c->size() > std::size_t(o.sor_neighbours) + 1) {
      Cloud::Ptr s(new Cloud);
      pcl::StatisticalOutlierRemoval<pcl::PointXYZ> sor;
      sor.setInputCloud(c);
      sor.setMeanK(o.sor_neighbours);
      sor.setStddevMulThresh(o.sor_std);
      sor.filter(*s);
      c = s;
    }
    if (o.ror_radius_m > 0 && !c->empty()) {
      Cloud::Ptr r(new Cloud);
      pcl::RadiusOutlierRemoval<pcl::PointXYZ> ror;
      ror.setInputCloud(c);
      ror.setRadiusSearch(o.ror_radius_m);
      ror.setMinNeighborsInRadius(o.ror_min_neighbours);
      ror.filter(*r);
      c = r;
    }
    for (const auto& p : *c) out.emplace_back(p.x, p.y, p.z);
  }
  return out;
}

// Sequential RANSAC: the best plane, remove its inliers, repeat.
std::vector<PrimitivePlane> detect_planes(const std::vector<Vec3>& points, const DenseOptions& o) {
  std::vector<PrimitivePlane> planes;
  Cloud::Ptr rest = to_pcl(points);
  pcl::SACSegmentation<pcl::PointXYZ> seg;
  seg.setOptimizeCoefficients(true);
  seg.setModelType(pcl::SACMODEL_PLANE);
  seg.setMethodType(pcl::SAC_RANSAC);
  seg.setDistanceThreshold(o.ransac_threshold_m);
  seg.setMaxIterations(500);
  while (int(planes.size()) < o.max_planes && rest->size() >= std::size_t(o.min_plane_points)) {
    pcl::PointIndices::Ptr in(new pcl::PointIndices);
    pcl::ModelCoefficients coef;
    seg.setInputCloud(rest);
    seg.segment(*in, coef);
    if (in->indices.size() < std::size_t(o.min_plane_points)) break;
    Vec3 n(coef.values[0], coef.values[1], coef.values[2]);
    double len = n.norm();
    planes.push_back(PrimitivePlane{n / len, coef.values[3] / len});
    Cloud::Ptr next(new Cloud);
    pcl::ExtractIndices<pcl::PointXYZ> ex;
    ex.setInputCloud(rest);
    ex.setIndices(in);
    ex.setNegative(true);
    ex.filter(*next);
    rest = next;
  }
  return planes;
}

TriMesh greedy_mesh(const std::vector<Vec3>& points, const DenseOptions& o) {
  TriMesh m;
  if (points.size() < 3) return m;
  Cloud::Ptr c = to_pcl(points);
  pcl::search::KdTree<pcl::PointXYZ>::Ptr tree(new pcl::search::KdTree<pcl::PointXYZ>);
  pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> ne;
  pcl::PointCloud<pcl::Normal>::Ptr normals(new pcl::PointCloud<pcl::Normal>);
  ne.setInputCloud(c);
  ne.setSearchMethod(tree);
  ne.setKSearch(20);
  ne.compute(*normals);
  pcl::PointCloud<pcl::PointNormal>::Ptr pn(new pcl::PointCloud<pcl::PointNormal>);
  pcl::concatenateFields(*c, *normals, *pn);
  pcl::search::KdTree<pcl::PointNormal>::Ptr tree2(new pcl::search::KdTree<pcl::PointNormal>);
  pcl::GreedyProjectionTriangulation<pcl::PointNormal> gp3;
  gp3.setSearchRadius(o.greedy_radius_m);
  gp3.setMu(2.5);
  gp3.setMaximumNearestNeighbors(100);
  gp3.setMaximumSurfaceAngle(M_PI / 4);
  gp3.setMinimumAngle(M_PI / 18);
  gp3.setMaximumAngle(2 * M_PI / 3);
  gp3.setNormalConsistency(false);
  gp3.setInputCloud(pn);
  gp3.setSearchMethod(tree2);
  std::vector<pcl::Vertices> polys;
  gp3.reconstruct(polys);
  m.vertices = points;
  for (const auto& p : polys)
    if (p.vertices.size() == 3)
      m.triangles.push_back({int(p.vertices[0]), int(p.vertices[1]), int(p.vertices[2])});
  return m;
}

DenseReport optimize_dense(TriMesh& mesh, const std::vector<Vec3>& points, const DenseOptions& o) {
  DenseReport r;
  r.input_points = points.size();
  std::vector<Vec3> kept = preprocess_points(points, o, &r.tiles);
  r.kept_points = kept.size();
  if (mesh.triangles.empty()) mesh = greedy_mesh(kept, o);
  r.triangles = mesh.triangles.size();
  ConstrainedMesh cm;
  cm.mesh = mesh;
  // Planes are found per tile and constrain only the triangles of their tile:
  // over a whole town a plane found on one roof must not pull another.
  auto tile_of = [&](const Vec3& p) {
    return std::make_pair(std::lround(std::floor(p.x() / o.tile_m)),
                          std::lround(std::floor(p.y() / o.tile_m)));
  };
  std::map<std::pair<long, long>, std::vector<Vec3>> tile_points;
  for (const Vec3& p : kept) tile_points[tile_of(p)].push_back(p);
  std::map<std::pair<long, long>, std::vector<int>> tile_planes;
  for (auto& [key, pts] : tile_points)
    for (const auto& pl : detect_planes(pts, o)) {
      tile_planes[key].push_back(static_cast<int>(cm.planes.size()));
      cm.planes.push_back(pl);
    }
  r.planes = static_cast<int>(cm.planes.size());
  const double cos_max = std::cos(o.assign_angle_deg * M_PI / 180);
  static const std::vector<int> kNone;
  for (const auto& t : mesh.triangles) {
    const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    Vec3 n = (b - a).cross(c - a).normalized(), m = (a + b + c) / 3.0;
    int best = -1;
    double best_d = o.assign_distance_m;
    auto it = tile_planes.find(tile_of(m));
    for (int k : it == tile_planes.end() ? kNone : it->second) {
      double d = std::fabs(cm.planes[k].distance(m));
      if (d <= best_d && std::fabs(n.dot(cm.planes[k].n)) >= cos_max) best = int(k), best_d = d;
    }
    cm.tri_plane.push_back(best);
    r.constrained_triangles += best >= 0;
  }
  cm.lines = adjacent_plane_lines(cm);
  DistanceOptions d;
  d.device = o.optimizer.device;
  auto mean = [](const std::vector<double>& v) {
    double s = 0;
    for (double x : v) s += x;
    return v.empty() ? 0.0 : s / double(v.size());
  };
  r.deviation_before = mean(point_to_mesh_distances(kept, cm.mesh.soup(), d));
  r.optimizer = optimize_mesh(cm, o.optimizer);
  r.deviation_after = mean(point_to_mesh_distances(kept, cm.mesh.soup(), d));
  mesh = cm.mesh;
  return r;
}

}  // namespace c3d
