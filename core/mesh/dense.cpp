#include "core/mesh/dense.h"

#include "core/mesh/open3d_mesh.h"
#include "core/mesh/point_index.h"

#include <CGAL/Advancing_front_surface_reconstruction.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/mst_orient_normals.h>
#include <CGAL/pca_estimate_normals.h>
#include <CGAL/property_map.h>

#include <algorithm>
#include <stdexcept>
#include <tuple>
#include <utility>

namespace c3d {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Vector = Kernel::Vector_3;

// Points spread less than this share of their extent across their last axis
// are flat to Qhull (an exactly flat roof; 1e-5 of it with noise passed).
constexpr double kFlat = 1e-6;

// Advancing front's priority: a candidate triangle with an edge longer than
// `longest` is never taken; otherwise CGAL's own (the smallest Delaunay sphere).
struct LongestEdge {
  double longest;
  template <typename Front, typename Cell>
  double operator()(const Front& front, Cell& c, const int& index) const {
    for (int a = 1; a <= 3; ++a) {
      const int b = a % 3 + 1;
      const double d2 = CGAL::squared_distance(c->vertex((index + a) % 4)->point(), c->vertex((index + b) % 4)->point());
      if (d2 > longest * longest) return front.infinity();
    }
    return front.smallest_radius_delaunay_sphere(c, index);
  }
};

// Each point's local spacing: the mean distance of its 16 nearest points to
// their nearest others, found as asked (a building scanned densely from the
// air and sparsely from the street has two spacings, and its walls' gaps are
// judged by theirs).
class LocalSpacing {
 public:
  LocalSpacing(const std::vector<Vec3>& points, const PointIndex& index)
      : index_(index), nearest_(points.size(), -1), local_(points.size(), -1) {}
  double at(int i) {
    double& l = local_[size_t(i)];
    if (l >= 0) return l;
    const std::vector<int> near = index_.nearest_k(size_t(i), 16);
    double sum = 0;
    for (int j : near) {
      double& d = nearest_[size_t(j)];
      if (d < 0) d = std::max(0.0, index_.nearest_other(size_t(j)));
      sum += d;
    }
    return l = sum / double(std::max<size_t>(1, near.size()));
  }

 private:
  const PointIndex& index_;
  std::vector<double> nearest_, local_;
};

// The faces with a corner or centre farther than two spacings from every
// point (the mean spacing, or the local one at the nearest point where that
// is more): Poisson's out-of-bounds faces, and an interpolating method's
// triangles across a gap (their corners are points).
DenseResult trimmed(TriMesh mesh, const std::vector<Vec3>& points, double spacing) {
  const PointIndex index(points);
  LocalSpacing local(points, index);
  const auto near = [&](const Vec3& p) {
    double d = 0;
    const int i = index.nearest_index(p, &d);
    return i >= 0 && d <= 2 * std::max(spacing, local.at(i));
  };
  std::vector<char> vertex_near(mesh.vertices.size());
  for (size_t v = 0; v < mesh.vertices.size(); ++v) vertex_near[v] = near(mesh.vertices[v]);
  const auto strays = [&](const std::array<int, 3>& t) {
    for (int c : t)
      if (!vertex_near[size_t(c)]) return true;
    return !near((mesh.vertices[size_t(t[0])] + mesh.vertices[size_t(t[1])] + mesh.vertices[size_t(t[2])]) / 3);
  };
  DenseResult r;
  const size_t before = mesh.triangles.size();
  mesh.triangles.erase(std::remove_if(mesh.triangles.begin(), mesh.triangles.end(), strays), mesh.triangles.end());
  r.trimmed = before - mesh.triangles.size();
  r.mesh = without_loose_vertices(mesh);
  return r;
}

TriMesh advancing_front(const std::vector<Vec3>& points, const PointSpacing& spacing) {
  std::vector<Point> pts;
  pts.reserve(points.size());
  for (const Vec3& p : points) pts.emplace_back(p.x(), p.y(), p.z());
  std::vector<std::array<std::size_t, 3>> facets;
  const double ball = pivoting_radii(spacing).back();
  CGAL::advancing_front_surface_reconstruction(pts.begin(), pts.end(), std::back_inserter(facets),
                                               LongestEdge{2 * ball});
  TriMesh mesh;
  mesh.vertices = points;
  for (const auto& f : facets) mesh.triangles.push_back({int(f[0]), int(f[1]), int(f[2])});
  return mesh;
}

TriMesh made_by(const std::vector<Vec3>& points, const PointSpacing& spacing, DenseMethod method) {
  switch (method) {
    case DenseMethod::AdvancingFront: return advancing_front(points, spacing);
    case DenseMethod::AlphaShape: {  // Qhull's tetrahedra need a volume: flat points crash Open3D
      const Vec3 spread = point_spread(points);
      return spread.z() > kFlat * spread.x() ? alpha_shape(points, spacing) : TriMesh{};
    }
    case DenseMethod::BallPivoting: return ball_pivoting(points, oriented_normals(points), spacing);
    default: return screened_poisson(points, oriented_normals(points), spacing);
  }
}

}  // namespace

const char* dense_method_name(DenseMethod m) {
  switch (m) {
    case DenseMethod::BallPivoting: return "pivot";
    case DenseMethod::AdvancingFront: return "front";
    case DenseMethod::Poisson: return "poisson";
    default: return "alpha";
  }
}

DenseMethod dense_method_named(const std::string& name) {
  for (DenseMethod m : {DenseMethod::BallPivoting, DenseMethod::AdvancingFront, DenseMethod::Poisson,
                        DenseMethod::AlphaShape})
    if (name == dense_method_name(m)) return m;
  throw std::invalid_argument("unknown dense method '" + name + "' (pivot, front, poisson, alpha)");
}

std::vector<Vec3> oriented_normals(const std::vector<Vec3>& points, int k) {
  // mst_orient_normals reorders the points: each keeps its index.
  using Tagged = std::tuple<Point, Vector, size_t>;
  std::vector<Tagged> pts;
  pts.reserve(points.size());
  for (size_t i = 0; i < points.size(); ++i) pts.emplace_back(Point(points[i].x(), points[i].y(), points[i].z()), Vector(0, 0, 0), i);
  const auto params = CGAL::parameters::point_map(CGAL::Nth_of_tuple_property_map<0, Tagged>())
                          .normal_map(CGAL::Nth_of_tuple_property_map<1, Tagged>());
  CGAL::pca_estimate_normals<CGAL::Sequential_tag>(pts, unsigned(k), params);
  CGAL::mst_orient_normals(pts, unsigned(k), params);
  std::vector<Vec3> normals(points.size(), Vec3::UnitZ());
  for (const Tagged& t : pts) {
    const Vector& n = std::get<1>(t);
    const Vec3 v(n.x(), n.y(), n.z());
    if (v.norm() > 0) normals[std::get<2>(t)] = v.normalized();
  }
  return normals;
}

DenseResult dense_mesh(const std::vector<Vec3>& points, const PointSpacing& spacing, DenseMethod method) {
  if (points.size() < 4 || spacing.mean <= 0) return {};
  return trimmed(made_by(points, spacing, method), points, spacing.mean);
}

}  // namespace c3d
