#include "core/mesh/mesh_distance.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <cmath>

namespace c3d {

namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Triangle = Kernel::Triangle_3;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, std::vector<Triangle>::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

Kernel::Point_3 point(const Vec3& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace

std::vector<double> distances_to_mesh(const std::vector<Vec3>& points, const TriMesh& mesh) {
  std::vector<Triangle> triangles;
  triangles.reserve(mesh.triangles.size());
  for (const auto& t : mesh.soup()) {
    const Triangle tri(point(t[0]), point(t[1]), point(t[2]));
    if (!tri.is_degenerate()) triangles.push_back(tri);
  }
  std::vector<double> d(points.size(), INFINITY);
  if (triangles.empty()) return d;
  Tree tree(triangles.begin(), triangles.end());
  tree.accelerate_distance_queries();
  for (size_t i = 0; i < points.size(); ++i) d[i] = std::sqrt(tree.squared_distance(point(points[i])));
  return d;
}

}  // namespace c3d
