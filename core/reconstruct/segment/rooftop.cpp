#include "core/reconstruct/segment/rooftop.h"

#include "core/log.h"

#include <Eigen/Eigenvalues>
#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace c3d {
namespace {

// Lift and stair housings, plant boxes and tanks cover a few to some 20 m2; a
// part larger than this standing above roofs all round is a storey (a tower
// on a podium) and stays.
constexpr double kMaxRooftopObjectM2 = 25.0;
// Roof points this near in plan meet a plane's rim: a box's own side and the
// scan's shadow beside it leave a strip about this wide without roof points.
constexpr double kContactReachM = 1.0;
// Higher above every roof plane it meets than this, a plane stands on the
// roof (as a loose point does, kMaxLooseRise in segmentation.cpp): an eave
// strip or a dormer meets its roof within the planes' noise.
constexpr double kMinStandingRiseM = 0.5;
// A housing rises a storey at most (a lift's machine room some 3.5 m): a
// plane higher above the roof all round is a tower or a storey.
constexpr double kMaxStandingRiseM = 4.0;
// Housings, boxes and tanks are compact (at most about twice as long as
// wide); a plane three times as long as wide or more is a strip of the roof
// itself (a parapet or a raised edge along the building, AHN3 row houses).
constexpr double kMinCompactness = 1.0 / 3.0;
// A wall under the rim: 3 points (a facade holds a few in an airborne
// building class) within 0.5 m in plan of the plane's points, a metre and
// more below the roof it meets (twice kMinStandingRiseM: below the roof's
// own noise and any sheet or strip on it).
constexpr double kWallReachM = 0.5;
constexpr double kWallDropM = 1.0;
constexpr int kMinWallPoints = 3;
// What it stands on is a roof when that lies a storey (2 m) above the
// terrain: a plane over a patch at ground level (a yard or a terrain patch in
// the building class, AHN3 09324) is a low building, not a box on a roof.
constexpr double kMinRoofAboveTerrainM = 2.0;
// The low tail of the rises judged (noise at the rim): the 10th percentile.
constexpr double kRiseQuantile = 0.1;
// Surrounded: roof met in at least 5 of the 8 directions around the plane's
// centre (a tower at a building's end or corner meets it in 2 or 3).
constexpr int kDirections = 8;
constexpr int kMinSurroundingDirections = 5;

pcl::PointCloud<pcl::PointXYZ>::Ptr plan_of_labelled(const std::vector<Vec3>& points, const Segmentation& seg,
                                                     std::vector<int>& index) {
  pcl::PointCloud<pcl::PointXYZ>::Ptr plan(new pcl::PointCloud<pcl::PointXYZ>);
  for (size_t i = 0; i < points.size(); ++i)
    if (seg.label[i] >= 0) {
      plan->push_back(pcl::PointXYZ(float(points[i].x()), float(points[i].y()), 0.f));
      index.push_back(int(i));
    }
  return plan;
}

// Per point of c that meets another plane: its rise above the plane of the
// nearest such point, and the direction (of kDirections) from c's centre it lies in.
struct Contacts {
  std::vector<double> rise;
  std::array<bool, kDirections> direction{};
  double lowest_roof = INFINITY;  // the lowest roof height met
};

// The points of `tree` (a plan cloud) that may lie within `reach` of one of
// `idx`'s points: those within the circle round their box, grown by `reach`
// (and a centimetre: the tree measures in float). Searching these alone keeps
// each query to the component's surroundings, not the density squared.
pcl::Indices near_points(const std::vector<Vec3>& points, const std::vector<int>& idx,
                         const pcl::KdTreeFLANN<pcl::PointXYZ>& tree, double reach) {
  Vec2 lo(INFINITY, INFINITY), hi(-INFINITY, -INFINITY);
  for (int i : idx) lo = lo.cwiseMin(points[size_t(i)].head<2>()), hi = hi.cwiseMax(points[size_t(i)].head<2>());
  const Vec2 mid = (lo + hi) / 2;
  pcl::Indices nn;
  std::vector<float> d2;
  tree.radiusSearch(pcl::PointXYZ(float(mid.x()), float(mid.y()), 0.f), (hi - lo).norm() / 2 + reach + 0.01, nn, d2);
  return nn;
}

// A k-d tree of some points of a plan cloud; `at[k]`: the cloud index of its k-th point.
struct SubTree {
  pcl::KdTreeFLANN<pcl::PointXYZ> tree;
  std::vector<int> at;
  bool empty() const { return at.empty(); }
};

SubTree sub_tree(const pcl::PointCloud<pcl::PointXYZ>& plan, std::vector<int> at) {
  SubTree t;
  t.at = std::move(at);
  if (t.at.empty()) return t;
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  for (int k : t.at) cloud->push_back(plan[size_t(k)]);
  t.tree.setInputCloud(cloud);
  return t;
}

Contacts contacts_of(const std::vector<Vec3>& points, const Segmentation& seg, int c,
                     const pcl::KdTreeFLANN<pcl::PointXYZ>& tree, const std::vector<int>& index) {
  Contacts out;
  const RoofComponent& comp = seg.components[size_t(c)];
  const Vec3& centre = comp.fit.centroid;
  std::vector<int> others;  // points of other planes around c
  for (int k : near_points(points, comp.points, tree, kContactReachM))
    if (seg.label[size_t(index[size_t(k)])] != c) others.push_back(k);
  const SubTree near = sub_tree(*tree.getInputCloud(), std::move(others));
  if (near.empty()) return out;
  const float reach2 = float(kContactReachM * kContactReachM);
  pcl::Indices nn;
  std::vector<float> d2;
  for (int i : comp.points) {
    const Vec3& p = points[size_t(i)];
    const pcl::PointXYZ q(float(p.x()), float(p.y()), 0.f);
    // the roof under the rim is the plane of the nearest point of another
    // plane: across a ridge, a gable's other side extended would stand
    // higher than the roof there
    if (near.tree.nearestKSearch(q, 1, nn, d2) != 1 || !(d2[0] < reach2)) continue;
    const int other = index[size_t(near.at[size_t(nn[0])])];
    const double z = seg.components[size_t(seg.label[size_t(other)])].fit.plane.z_at(p.x(), p.y());
    if (!std::isfinite(z)) continue;
    out.rise.push_back(p.z() - z);
    out.lowest_roof = std::min(out.lowest_roof, z);
    const double a = std::atan2(p.y() - centre.y(), p.x() - centre.x()) + M_PI;  // 0 .. 2 pi
    out.direction[size_t(std::min(kDirections - 1, int(a / (2 * M_PI) * kDirections)))] = true;
  }
  return out;
}

// Width over length of the points in plan (the square root of the ratio of
// their plan covariance's eigenvalues).
double compactness(const std::vector<Vec3>& points, const std::vector<int>& idx) {
  Vec2 mean(0, 0);
  for (int i : idx) mean += points[size_t(i)].head<2>();
  mean /= double(idx.size());
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (int i : idx) {
    const Vec2 d = points[size_t(i)].head<2>() - mean;
    cov += d * d.transpose();
  }
  const Eigen::Vector2d ev = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(cov).eigenvalues();  // ascending
  return ev(1) > 0 ? std::sqrt(std::max(0.0, ev(0)) / ev(1)) : 0.0;
}

// The points in plan: every point, and the points of the planes (`index`:
// their indices into the points).
struct PlanTrees {
  pcl::KdTreeFLANN<pcl::PointXYZ> all, planes;
  std::vector<int> index;
  const Terrain* terrain = nullptr;
};

// Whether the roof met at `lowest_roof` under c's centre stands a storey
// above the terrain (true where the terrain is not known there).
bool on_a_raised_roof(const RoofComponent& comp, double lowest_roof, const Terrain& terrain) {
  if (!terrain) return true;
  const double ground = terrain(comp.fit.centroid.x(), comp.fit.centroid.y());
  return !std::isfinite(ground) || lowest_roof - ground >= kMinRoofAboveTerrainM;
}

// Whether a wall goes down under c's rim: points within kWallReachM in plan
// of c's points lying kWallDropM and more below the lowest roof c meets. A
// parapet or a raised edge along a facade has the facade under it (an
// airborne building class holds a few of its points); a box on a roof ends
// at the roof.
bool wall_under(const std::vector<Vec3>& points, const RoofComponent& comp, double lowest_roof,
                const pcl::KdTreeFLANN<pcl::PointXYZ>& all) {
  std::vector<int> low;  // points around c below the roof it meets
  for (int k : near_points(points, comp.points, all, kWallReachM))
    if (points[size_t(k)].z() < lowest_roof - kWallDropM) low.push_back(k);
  if (int(low.size()) < kMinWallPoints) return false;
  const SubTree below = sub_tree(*all.getInputCloud(), std::move(low));
  std::vector<char> seen(below.at.size(), 0);
  int count = 0;
  pcl::Indices nn;
  std::vector<float> d2;
  for (int i : comp.points) {
    const Vec3& p = points[size_t(i)];
    below.tree.radiusSearch(pcl::PointXYZ(float(p.x()), float(p.y()), 0.f), kWallReachM, nn, d2);
    for (int k : nn)
      if (!seen[size_t(k)]) seen[size_t(k)] = 1, ++count;
    if (count >= kMinWallPoints) return true;
  }
  return false;
}

bool stands(const std::vector<Vec3>& points, const Segmentation& seg, int c, const PlanTrees& t) {
  const pcl::KdTreeFLANN<pcl::PointXYZ>& tree = t.planes;
  const std::vector<int>& index = t.index;
  const RoofComponent& comp = seg.components[size_t(c)];
  if (seg.density <= 0 || double(comp.points.size()) / seg.density > kMaxRooftopObjectM2) return false;
  if (compactness(points, comp.points) < kMinCompactness) return false;
  Contacts k = contacts_of(points, seg, c, tree, index);
  if (k.rise.empty()) return false;
  if (std::count(k.direction.begin(), k.direction.end(), true) < kMinSurroundingDirections) return false;
  const auto low = k.rise.begin() + long(kRiseQuantile * double(k.rise.size()));
  std::nth_element(k.rise.begin(), low, k.rise.end());
  if (*low <= kMinStandingRiseM || *low > kMaxStandingRiseM) return false;
  if (wall_under(points, comp, k.lowest_roof, t.all)) return false;
  if (t.terrain && !on_a_raised_roof(comp, k.lowest_roof, *t.terrain)) return false;
  log::debug(log::format("rooftop object: plane of %zu points at (%.2f %.2f %.2f) stands %.2f m above the roof",
                         comp.points.size(), comp.fit.centroid.x(), comp.fit.centroid.y(), comp.fit.centroid.z(), *low));
  return true;
}

}  // namespace

void drop_rooftop_objects(const std::vector<Vec3>& points, Segmentation& seg, const Terrain& terrain) {
  if (seg.components.size() < 2) return;
  PlanTrees t;
  t.terrain = &terrain;
  t.planes.setInputCloud(plan_of_labelled(points, seg, t.index));
  pcl::PointCloud<pcl::PointXYZ>::Ptr plan(new pcl::PointCloud<pcl::PointXYZ>);
  for (const Vec3& p : points) plan->push_back(pcl::PointXYZ(float(p.x()), float(p.y()), 0.f));
  t.all.setInputCloud(plan);
  std::vector<int> new_id(seg.components.size(), -1);
  std::vector<RoofComponent> kept;
  for (size_t c = 0; c < seg.components.size(); ++c) {  // judged against all: one lid does not hide another
    if (stands(points, seg, int(c), t)) continue;
    new_id[c] = int(kept.size());
    kept.push_back(seg.components[c]);
  }
  if (kept.size() == seg.components.size()) return;
  for (int& l : seg.label)
    if (l >= 0) l = new_id[size_t(l)];
  seg.components = std::move(kept);
}

}  // namespace c3d
