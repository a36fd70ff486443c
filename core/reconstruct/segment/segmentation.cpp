#include "core/reconstruct/segment/segmentation.h"

#include "core/geometry/unique_points.h"
#include "core/reconstruct/planes/ransac.h"
#include "core/reconstruct/segment/clusters.h"
#include "core/reconstruct/segment/coplanar.h"
#include "core/reconstruct/segment/neighbours.h"
#include "core/reconstruct/segment/normals.h"
#include "core/reconstruct/segment/rooftop.h"

#include <pcl/features/normal_3d_omp.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/region_growing.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>

namespace c3d {
namespace {

// A surface steeper than 60 degrees (a tank's side, a parapet's face) is not
// roof: neither a loose point on it nor a plane the second pass grows there.
// Corrugated sheet tilts its normals by up to ~45.
constexpr double kMinRoofNormalZ = 0.5;  // cos 60 degrees
// No roof is steeper than 75 degrees: a plane that is (the facade points an
// airborne "building" class holds) is a wall seen from the air, and lifted as
// a roof it runs to kilometres (AHN3: 14 buildings with planes of 80-90
// degrees, heights from -47 km to +11 km). Mansard faces stay below it.
constexpr double kMinPlaneNormalZ = 0.2588;  // cos 75 degrees
constexpr int kNormalNeighbours = 16;    // normals, and the smoothing of the second pass
// A roof cluster region growing leaves without a plane is one roof plane when
// most of its points lie on one (a sparse scan's shed: its 16-point normals
// span the whole roof and its edges, and no region grows to the minimum);
// a tree crown or a noisy heap has a fifth of its points on any plane.
constexpr double kMinPlanarShare = 0.6;
// The spacing of a scan of density rho is at least this over sqrt(rho): points
// strewn at random lie 0.47 / sqrt(rho) from their nearest (median), and a scan
// covers a roof at least as evenly; a median nearest distance below it comes
// from clumps (points on scan rows 0.5 m apart, 3 cm within a row), and taken
// for the spacing it shrinks every gap and area measured in spacings.
constexpr double kMinSpacingPerCoverage = 0.5;
// Roofs are apart across a gap a quarter wider than the widest the sampling
// leaves around a point (sampling_gap): scan rows 0.5 m apart on a 30-degree
// slope lie 0.58 m apart, more than 4 in-row spacings.
constexpr double kGapsPerRoofGap = 1.25;

using Cloud = pcl::PointCloud<pcl::PointXYZ>;
using Tree = pcl::search::KdTree<pcl::PointXYZ>;

// Region growing that hands back the neighbour lists it searched, so the
// reassignment of points to planes does not search the same roof again.
class RegionGrowingKeepingNeighbours : public pcl::RegionGrowing<pcl::PointXYZ, pcl::Normal> {
 public:
  std::vector<pcl::Indices> take_neighbours() { return std::move(point_neighbours_); }
};

Cloud::Ptr to_pcl(const std::vector<Vec3>& pts) {
  Cloud::Ptr c(new Cloud);
  c->reserve(pts.size());
  for (const auto& p : pts) c->push_back(pcl::PointXYZ(float(p.x()), float(p.y()), float(p.z())));
  return c;
}

// Median plan distance to the nearest other point: the scan's point spacing,
// and never closer than points strewn at random at `density` would lie (0:
// unknown), which rows or clumps of points would otherwise pass for.
double median_spacing(const Cloud::Ptr& cloud, const NeighbourTable& table, double density) {
  std::vector<double> d;
  pcl::Indices nn(2);
  std::vector<float> dist(2);
  size_t step = std::max<size_t>(1, cloud->size() / 2000);
  for (size_t i = 0; i < cloud->size(); i += step)
    if (table.nearestKSearch(int(i), 2, nn, dist) == 2) d.push_back(std::sqrt(dist[1]));
  if (d.empty()) return 0.2;
  std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
  const double coverage = density > 0 ? kMinSpacingPerCoverage / std::sqrt(density) : 0.0;
  return std::max({d[d.size() / 2], coverage, kSamePlaceM});
}

// Median over the points of the points per m2 within their 16 nearest: the
// scan's density, near enough for the fewest points a roof plane may hold.
double median_density(const Cloud::Ptr& cloud, const NeighbourTable& table) {
  std::vector<double> rho;
  pcl::Indices nn(kNormalNeighbours);
  std::vector<float> d2(kNormalNeighbours);
  size_t step = std::max<size_t>(1, cloud->size() / 2000);
  for (size_t i = 0; i < cloud->size(); i += step)
    if (table.nearestKSearch(int(i), kNormalNeighbours, nn, d2) == kNormalNeighbours && d2.back() > 0)
      rho.push_back(double(kNormalNeighbours - 1) / (M_PI * double(d2.back())));
  if (rho.empty()) return 0;
  std::nth_element(rho.begin(), rho.begin() + long(rho.size() / 2), rho.end());
  return rho[rho.size() / 2];
}

std::vector<pcl::PointIndices> cluster_roofs(const Cloud::Ptr& cloud, const pcl::Indices& kept, double tolerance,
                                             int min_points) {
  return euclidean_clusters(*cloud, kept, float(tolerance), size_t(std::max(min_points, 0)),
                            std::numeric_limits<int>::max());
}

// Planar regions of one roof, and each roof point's nearest roof points
// (indexed by point, sorted by distance, the point itself first).
std::vector<pcl::PointIndices> grow_components(const Cloud::Ptr& cloud,
                                               const pcl::PointCloud<pcl::Normal>::Ptr& normals,
                                               const pcl::Indices& roof,
                                               const ReconstructionParams& p, int k,
                                               std::vector<pcl::Indices>& neighbours) {
  RegionGrowingKeepingNeighbours rg;
  rg.setMinClusterSize(std::max(5, p.min_component_points / 3));
  rg.setMaxClusterSize(std::numeric_limits<int>::max());
  rg.setSearchMethod(Tree::Ptr(new Tree));  // its own: extract() re-indexes the tree
  rg.setNumberOfNeighbours(k);
  rg.setInputCloud(cloud);
  rg.setIndices(pcl::make_shared<pcl::Indices>(roof));
  rg.setInputNormals(normals);
  rg.setSmoothnessThreshold(float(p.component_smoothness_deg * M_PI / 180.0));
  rg.setCurvatureThreshold(float(p.component_curvature));
  rg.setSmoothModeFlag(false);  // compare with the seed normal: no drift across hips and ridges
  std::vector<pcl::PointIndices> regions;
  rg.extract(regions);
  neighbours = rg.take_neighbours();
  return regions;
}

// Gives every roof point to the component whose plane fits it best among the
// components of its 12 nearest roof points; points no plane explains stay unlabelled.
void reassign(const std::vector<Vec3>& pts, const std::vector<pcl::Indices>& neighbours,
              const pcl::Indices& roof, const pcl::Indices& which, std::vector<RoofComponent>& comps,
              std::vector<int>& label, double tol) {
  std::vector<int> old = label;
  static const pcl::Indices none;  // region growing gave up before searching
  for (int i : which) {
    const auto& nn = size_t(i) < neighbours.size() ? neighbours[size_t(i)] : none;
    int best = -1;
    double best_d = 1e9;
    for (size_t n = 0; n < std::min<size_t>(12, nn.size()); ++n) {
      int k = nn[n];
      int c = old[k];
      if (c < 0) continue;
      double d = std::abs(comps[c].fit.plane.distance(pts[i]));
      if (d < best_d) best_d = d, best = c;
    }
    double limit = best >= 0 ? std::max(3.0 * comps[best].fit.rmse, tol) : 0;
    label[i] = (best >= 0 && best_d <= limit) ? best : -1;
  }
  for (auto& c : comps) c.points.clear();
  for (int i : roof)
    if (label[i] >= 0) comps[label[i]].points.push_back(i);
}

// Labels of one roof's points from its components' point lists.
void relabel(const pcl::Indices& roof, const std::vector<RoofComponent>& comps, std::vector<int>& label) {
  for (int i : roof) label[i] = -1;
  for (size_t c = 0; c < comps.size(); ++c)
    for (int i : comps[c].points) label[i] = int(c);
}

// Merges coplanar regions, then gives the points of `which` (the rest keep
// their labels) to their best-fitting planes, twice, refitting in between.
void settle_labels(const std::vector<Vec3>& pts, const std::vector<pcl::Indices>& neighbours,
                   const pcl::Indices& roof, const pcl::Indices& which, double tol,
                   std::vector<RoofComponent>& comps, std::vector<int>& label) {
  merge_coplanar(pts, comps, tol);
  relabel(roof, comps, label);
  for (int round = 0; round < 2; ++round) {
    reassign(pts, neighbours, roof, which, comps, label, tol);
    for (auto& c : comps)
      if (c.points.size() >= 3) c.fit = fit_plane_robust(pts, c.points, tol);
  }
}

// Regions as components of one roof, those of `min_points` or more; with
// `min_normal_z`, steeper planes (a tank's side, a parapet's face) are left out.
void add_regions(const std::vector<Vec3>& pts, const std::vector<pcl::PointIndices>& regions,
                 const ReconstructionParams& p, int roof, std::vector<RoofComponent>& comps,
                 size_t min_points = 0, double min_normal_z = 0.0) {
  for (const auto& region : regions) {
    if (region.indices.size() < min_points) continue;
    RoofComponent c;
    c.points.assign(region.indices.begin(), region.indices.end());
    c.fit = fit_plane_robust(pts, c.points, p.plane_inlier_m);
    if (std::abs(c.fit.plane.n.z()) < min_normal_z) continue;
    c.roof = roof;
    comps.push_back(std::move(c));
  }
}

// Kept as a roof plane: enough points to judge a plane at the scan's density,
// standing for enough plan area there (1 / density m2 each: the scan's own
// measure, whatever pattern its points lie in).
bool big_enough(const RoofComponent& c, double density, const ReconstructionParams& p) {
  const int n = int(c.points.size());
  return n >= min_plane_points(density, p) && double(n) >= density * p.min_component_area_m2;
}

// Each point of `which` (on roof `roof`) gets into `out` the mean of the
// (upward) normals of its nearest neighbours on that roof, itself included.
// Curvature 0: any point may seed.
void smooth_normals(const NeighbourTable& table, const pcl::PointCloud<pcl::Normal>& normals,
                    const std::vector<int>& roof_of_point, int roof, const pcl::Indices& which,
                    pcl::PointCloud<pcl::Normal>& out) {
  pcl::Indices nn;
  std::vector<float> d2;
  for (int i : which) {
    table.nearestKSearch(i, kNormalNeighbours, nn, d2);
    Vec3 sum = Vec3::Zero();
    for (int j : nn) {
      const auto& q = normals[size_t(j)];
      if (roof_of_point[size_t(j)] != roof || !std::isfinite(q.normal_z)) continue;
      Vec3 v(q.normal_x, q.normal_y, q.normal_z);
      sum += v.z() < 0 ? -v : v;
    }
    if (sum.norm() == 0) continue;
    sum.normalize();
    auto& o = out[size_t(i)];
    o.normal_x = float(sum.x()), o.normal_y = float(sum.y()), o.normal_z = float(sum.z()), o.curvature = 0.f;
  }
}

// What one roof's planes are grown from.
struct RoofScene {
  const std::vector<Vec3>& points;
  const Cloud::Ptr& cloud;
  const NeighbourTable& table;
  const pcl::PointCloud<pcl::Normal>::Ptr& normals;
  int neighbours;                      // region growing's: those the normals were taken from
  const std::vector<int>& cluster_of;  // per point: its roof cluster
  const ReconstructionParams& p;
};

// The planar components region growing finds on roof cluster `r` (some may
// still be too small to keep). `smooth`: the second pass's normals, made on
// first use.
std::vector<RoofComponent> roof_components(const RoofScene& s, int r, const pcl::Indices& roof,
                                           const Segmentation& seg, pcl::PointCloud<pcl::Normal>::Ptr& smooth) {
  const auto& points = s.points;
  const auto& p = s.p;
  std::vector<RoofComponent> comps;
  std::vector<pcl::Indices> roof_neighbours;  // neighbours never come from another roof
  add_regions(points, grow_components(s.cloud, s.normals, roof, p, s.neighbours, roof_neighbours), p, seg.roof_count, comps, 0,
              kMinPlaneNormalZ);
  std::vector<int> local_label(points.size(), -1);
  settle_labels(points, roof_neighbours, roof, roof, p.plane_inlier_m, comps, local_label);
  // Second pass over what the first left: textured sheet (corrugation, tiles)
  // tilts the 16-point normals by 20-45 degrees, so region growing breaks such
  // roofs into patches too small to keep. Averaged over the neighbours, the
  // normals follow the sheet, and the patches grow into planes.
  comps.erase(std::remove_if(comps.begin(), comps.end(),
                             [&](const RoofComponent& c) { return !big_enough(c, seg.density, p); }),
              comps.end());
  relabel(roof, comps, local_label);
  pcl::Indices leftover;
  for (int i : roof)
    if (local_label[i] < 0) leftover.push_back(i);
  const int min_points = min_plane_points(seg.density, p);
  if (int(leftover.size()) >= min_points) {
    if (!smooth) smooth.reset(new pcl::PointCloud<pcl::Normal>(*s.normals));
    smooth_normals(s.table, *s.normals, s.cluster_of, r, leftover, *smooth);
    std::vector<pcl::Indices> unused;
    size_t before = comps.size();
    add_regions(points, grow_components(s.cloud, smooth, leftover, p, s.neighbours, unused), p, seg.roof_count, comps,
                size_t(min_points), kMinRoofNormalZ);
    if (comps.size() > before)
      settle_labels(points, roof_neighbours, roof, leftover, p.plane_inlier_m, comps, local_label);
  }
  return comps;
}

// A roof cluster that region growing left without a plane, as one plane
// (kMinPlanarShare): the plane most of its points lie within plane_inlier_m
// of, no wall, its points enough for the scan's density and covering
// min_component_area_m2 in plan. Its points off that plane stay unlabelled.
std::optional<RoofComponent> planar_cluster(const std::vector<Vec3>& points, const pcl::Indices& roof,
                                            double density, const ReconstructionParams& p) {
  const std::vector<int> idx(roof.begin(), roof.end());
  PlaneSample best = sample_plane_consensus(points, idx, p.plane_inlier_m, kMinRoofNormalZ);
  const int n = int(best.inliers.size());
  if (n < min_plane_points(density, p) || double(n) < kMinPlanarShare * double(idx.size()) ||
      plan_hull_area(points, best.inliers) < p.min_component_area_m2)
    return std::nullopt;
  RoofComponent c;
  c.points = std::move(best.inliers);
  c.fit = fit_plane_robust(points, c.points, p.plane_inlier_m);
  c.min_points = min_plane_points(density, p);
  return c;
}

// Adds a component to the segmentation, labelling its points.
void keep_component(RoofComponent c, Segmentation& seg) {
  const int id = int(seg.components.size());
  for (int i : c.points) seg.label[size_t(i)] = id;
  seg.components.push_back(std::move(c));
}

}  // namespace

int min_plane_points(double density, const ReconstructionParams& p) {
  const int at_density = int(std::ceil(density * p.min_component_area_m2));
  return std::max(kMinPlanePoints, std::min(p.min_component_points, at_density));
}

namespace {

// segment_roofs on points no two of which are one place.
Segmentation segment_places(const std::vector<Vec3>& points, const ReconstructionParams& p, const Terrain& terrain) {
  Segmentation seg;
  seg.label.assign(points.size(), -1);
  seg.roof_of.assign(points.size(), -1);
  if (points.size() < 10) return seg;
  auto cloud = to_pcl(points);
  auto table = std::make_shared<NeighbourTable>(cloud, std::max(kNormalNeighbours, p.outlier_neighbours + 1));
  seg.density = median_density(cloud, *table);
  seg.spacing = median_spacing(cloud, *table, seg.density);

  pcl::Indices kept = remove_statistical_outliers(*table, p.outlier_neighbours, p.outlier_std);
  const PointNormals estimated = estimate_normals(cloud, table, kNormalNeighbours);
  const pcl::PointCloud<pcl::Normal>::Ptr& normals = estimated.normals;

  double tolerance = p.roof_cluster_m > 0 ? p.roof_cluster_m
                                          : std::max({0.5, 4.0 * seg.spacing, kGapsPerRoofGap * sampling_gap(cloud, *table)});
  // Clusters as small as a sparse scan's plane: one no region grows on may still be a plane.
  auto roofs = cluster_roofs(cloud, kept, tolerance, min_plane_points(seg.density, p));
  std::vector<int> cluster_of(points.size(), -1);
  for (size_t r = 0; r < roofs.size(); ++r)
    for (int i : roofs[r].indices) cluster_of[size_t(i)] = int(r);
  // The second pass's normals: one copy for the scene, each roof smoothing
  // only its own left-over points (region growing reads no others).
  pcl::PointCloud<pcl::Normal>::Ptr smooth;
  for (size_t r = 0; r < roofs.size(); ++r) {
    const auto& roof = roofs[r];
    const RoofScene scene{points, cloud, *table, normals, estimated.neighbours, cluster_of, p};
    std::vector<RoofComponent> comps = roof_components(scene, int(r), roof.indices, seg, smooth);
    int kept_here = 0;
    for (auto& c : comps) {
      if (!big_enough(c, seg.density, p)) continue;
      c.min_points = min_plane_points(seg.density, p);
      keep_component(std::move(c), seg);
      ++kept_here;
    }
    if (kept_here == 0) {
      std::optional<RoofComponent> planar = planar_cluster(points, roof.indices, seg.density, p);
      if (!planar) continue;
      planar->roof = seg.roof_count;
      keep_component(std::move(*planar), seg);
    }
    for (int i : roof.indices)  // a steep surface no plane took is not roof (kMinRoofNormalZ)
      if (seg.label[i] >= 0 || std::abs((*normals)[size_t(i)].normal_z) >= kMinRoofNormalZ)
        seg.roof_of[i] = seg.roof_count;
    ++seg.roof_count;
  }
  drop_rooftop_objects(points, seg, terrain);
  return seg;
}

// The segmentation of the places, spread to every copy of each: a copy has its
// place's labels and joins its components.
Segmentation spread_to_copies(Segmentation places, const UniquePoints& u) {
  std::vector<std::vector<int>> copies(u.unique.size());
  for (size_t i = 0; i < u.of.size(); ++i) copies[size_t(u.of[i])].push_back(int(i));
  Segmentation seg = std::move(places);
  std::vector<int> label(u.of.size()), roof_of(u.of.size());
  for (size_t i = 0; i < u.of.size(); ++i) {
    label[i] = seg.label[size_t(u.of[i])];
    roof_of[i] = seg.roof_of[size_t(u.of[i])];
  }
  seg.label = std::move(label);
  seg.roof_of = std::move(roof_of);
  for (auto& c : seg.components) {
    std::vector<int> all;
    for (int k : c.points) all.insert(all.end(), copies[size_t(k)].begin(), copies[size_t(k)].end());
    c.points = std::move(all);
  }
  return seg;
}

}  // namespace

// Neighbourhoods, spacing and density are the scan's places': four copies of
// four places fix no normal, and a copy 0 m away is no spacing.
Segmentation segment_roofs(const std::vector<Vec3>& points, const ReconstructionParams& p,
                           const Terrain& terrain) {
  UniquePoints u = unique_points(points, kSamePlaceM);
  if (u.unique.size() == points.size()) return segment_places(points, p, terrain);
  std::vector<Vec3> places;
  places.reserve(u.unique.size());
  for (int i : u.unique) places.push_back(points[size_t(i)]);
  return spread_to_copies(segment_places(places, p, terrain), u);
}

// Higher above the nearest plane than this, a loose point stands on the roof
// (a tank's lid, an antenna) rather than being part of it: a textured eave
// strip rises a few decimetres at most.
constexpr double kMaxLooseRise = 0.5;  // m

std::vector<std::vector<int>> loose_roof_points(const std::vector<Vec3>& points, const Segmentation& seg,
                                                double reach) {
  std::vector<std::vector<int>> taken(size_t(seg.roof_count)), loose(size_t(seg.roof_count));
  for (size_t i = 0; i < points.size(); ++i) {
    if (seg.roof_of[i] < 0) continue;
    (seg.label[i] >= 0 ? taken : loose)[size_t(seg.roof_of[i])].push_back(int(i));
  }
  std::vector<std::vector<int>> out(loose.size());
  for (size_t r = 0; r < loose.size(); ++r) {
    if (taken[r].empty() || loose[r].empty()) continue;
    Cloud::Ptr plan(new Cloud);
    for (int i : taken[r]) plan->push_back(pcl::PointXYZ(float(points[i].x()), float(points[i].y()), 0.f));
    Tree tree;
    tree.setInputCloud(plan);
    pcl::Indices nn(1);
    std::vector<float> d2(1);
    for (int i : loose[r]) {
      pcl::PointXYZ q(float(points[i].x()), float(points[i].y()), 0.f);
      if (tree.nearestKSearch(q, 1, nn, d2) != 1 || d2[0] > reach * reach) continue;
      const Plane& nearest = seg.components[size_t(seg.label[size_t(taken[r][size_t(nn[0])])])].fit.plane;
      const double above = nearest.distance(points[i]) * (nearest.n.z() < 0 ? -1 : 1);
      if (above <= kMaxLooseRise) out[r].push_back(i);
    }
  }
  return out;
}

}  // namespace c3d
