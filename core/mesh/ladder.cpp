#include "core/mesh/ladder.h"

#include <algorithm>

#include "core/cpu_clock.h"
#include "core/mesh/open3d_mesh.h"

namespace c3d {

namespace {

size_t share_of(size_t faces, double share) { return std::max<size_t>(4, size_t(double(faces) * share)); }

// A gap the largest pivoting ball could not cross, twice over: a border up
// to 4 balls' diameters long closes a sampling gap, not an opening.
double small_hole(const PointSpacing& s) { return 8 * pivoting_radii(s).back(); }

// A region is flat where its vertices keep within half a spacing of a plane,
// or within 2.5 noise sigma where the scan is noisier than that.
RegionParams region_params(const PointSpacing& s) {
  RegionParams p;
  p.flat_m = std::max(s.mean / 2, 2.5 * s.noise);
  return p;
}

}  // namespace

void simplify_levels(MeshLadder& l, Simplifier simplifier, const std::vector<Vec3>& points) {
  l.simplifier = simplifier;
  MeshLevel& l4 = l.levels[3];
  const std::vector<RegionFrame> frames = planar_frames(l4.mesh, l.regions);
  l4.planar = region_shapes(l4.mesh, l4.face_region, frames);
  const std::vector<Vec3> borders = border_vertices(l4.mesh, l4.face_region);
  const size_t dense_faces = l4.mesh.triangles.size();
  for (auto [k, share] : {std::pair{3, kLevel3Share}, {2, kLevel2Share}}) {
    const double t = thread_cpu_seconds();
    MeshLevel& level = l.levels[size_t(k - 1)];
    // From the level above, whose faces keep their level-4 regions.
    const MeshLevel& above = l.levels[size_t(k)];
    // No vertex moves past two spacings: as far as level 4 may stray from the points.
    Simplified light = simplified(above.mesh, share_of(dense_faces, share), small_hole(l.spacing), 2 * l.spacing.mean,
                                  MeshRegions{above.face_region, l.regions.kinds, l.regions.extremes}, simplifier);
    level.seconds = thread_cpu_seconds() - t;
    level.mesh = std::move(light.mesh);
    level.face_region = std::move(light.face_region);
    level.planar = region_shapes(level.mesh, level.face_region, frames);
    level.change = planar_change(l4.planar, level.planar);
    level.border_shift = spread_of(distances_to(level.mesh, borders));
    level.metrics = measure_mesh(level.mesh, points, l.spacing);
  }
}

MeshLadder mesh_ladder(const std::vector<Vec3>& points, DenseMethod method, const HullClosure& closure,
                       Simplifier simplifier) {
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
  l.regions = segment_regions(l4.mesh, region_params(l.spacing));
  l4.face_region = l.regions.face_region;
  l4.seconds = thread_cpu_seconds() - t;
  l4.metrics = measure_mesh(l4.mesh, points, l.spacing);
  simplify_levels(l, simplifier, points);
  t = thread_cpu_seconds();
  std::vector<Vec3> closed = points;
  if (closure) {
    const std::vector<Vec3> ground = closure(l.spacing.mean);
    closed.insert(closed.end(), ground.begin(), ground.end());
  }
  // The hull's budget is its own, not a share of level 4: it must follow a
  // small building's shape closely enough to check its model by (a share of a
  // few hundred faces wraps a shed in a blob).
  Wrap hull = wrapped(closed, kLevel1MaxFaces);
  l.levels[0].mesh = std::move(hull.mesh);
  l.hull_alpha = hull.alpha;
  l.hull_offset = hull.offset;
  l.levels[0].seconds = thread_cpu_seconds() - t;
  l.levels[0].metrics = measure_mesh(l.levels[0].mesh, points, l.spacing);
  return l;
}

}  // namespace c3d
