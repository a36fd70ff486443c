#include "core/mesh/ladder.h"

#include <algorithm>

#include "core/cpu_clock.h"
#include "core/mesh/open3d_mesh.h"
#include "core/mesh/simplify.h"

namespace c3d {

namespace {

size_t share_of(size_t faces, double share) { return std::max<size_t>(4, size_t(double(faces) * share)); }

// A gap the largest pivoting ball could not cross, twice over: a border up
// to 4 balls' diameters long closes a sampling gap, not an opening.
double small_hole(const PointSpacing& s) { return 8 * pivoting_radii(s).back(); }

// A region is flat where its vertices keep within half a spacing of a plane.
RegionParams region_params(const PointSpacing& s) {
  RegionParams p;
  p.flat_m = s.mean / 2;
  return p;
}

}  // namespace

MeshLadder mesh_ladder(const std::vector<Vec3>& points, DenseMethod method, const std::vector<Vec3>& ground) {
  MeshLadder l;
  l.method = method;
  for (int k = 1; k <= 4; ++k) l.levels[size_t(k - 1)].level = k;
  if (points.size() < 4) return l;
  double t = thread_cpu_seconds();
  l.spacing = point_spacing(points);
  DenseResult dense = dense_mesh(points, l.spacing, method);
  l.trimmed = dense.trimmed;
  MeshLevel& l4 = l.levels[3];
  l4.mesh = std::move(dense.mesh);
  l4.seconds = thread_cpu_seconds() - t;
  const size_t dense_faces = l4.mesh.triangles.size();
  // Not yet kept by the simplification: kept whole on the scanned box, the
  // borders of a Poisson mesh's rounded edges cost its level 3 a third more
  // deviation (docs/meshes.md); per-region retention comes first.
  l.regions = segment_regions(l4.mesh, region_params(l.spacing));
  for (auto [k, share] : {std::pair{3, kLevel3Share}, {2, kLevel2Share}}) {
    t = thread_cpu_seconds();
    MeshLevel& level = l.levels[size_t(k - 1)];
    level.mesh = simplified(l.levels[size_t(k)].mesh, share_of(dense_faces, share), small_hole(l.spacing),
                            2 * l.spacing.mean);  // as level 4 may stray from the points
    level.seconds = thread_cpu_seconds() - t;
  }
  t = thread_cpu_seconds();
  std::vector<Vec3> closed = points;
  closed.insert(closed.end(), ground.begin(), ground.end());
  // The hull's budget is its own, not a share of level 4: it must follow a
  // small building's shape closely enough to check its model by (a share of a
  // few hundred faces wraps a shed in a blob).
  const size_t hull_faces = kLevel1MaxFaces;
  Wrap hull = wrapped(closed, hull_faces);
  l.levels[0].mesh = std::move(hull.mesh);
  l.hull_alpha = hull.alpha;
  l.hull_offset = hull.offset;
  l.levels[0].seconds = thread_cpu_seconds() - t;
  for (MeshLevel& level : l.levels) level.metrics = measure_mesh(level.mesh, points, l.spacing);
  return l;
}

}  // namespace c3d
