#include "core/primitives/primitives.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Orthogonal_k_neighbor_search.h>
#include <CGAL/Search_traits_3.h>
#include <CGAL/Shape_detection/Efficient_RANSAC.h>
#include <CGAL/convex_hull_2.h>
#include <CGAL/property_map.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <tuple>

#include "core/primitives/least_squares.h"

namespace c3d {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
// A point, its normal and its index: RANSAC reorders its input.
using Pwn = std::tuple<Kernel::Point_3, Kernel::Vector_3, int>;
using PwnVector = std::vector<Pwn>;
using Traits =
    CGAL::Shape_detection::Efficient_RANSAC_traits<Kernel, PwnVector, CGAL::Nth_of_tuple_property_map<0, Pwn>,
                                                   CGAL::Nth_of_tuple_property_map<1, Pwn>>;
using Ransac = CGAL::Shape_detection::Efficient_RANSAC<Traits>;

constexpr double kPi = 3.14159265358979323846;
constexpr int kNeighbours = 16;
constexpr size_t kMaxPoints = 3000;

Vec3 vec(const Kernel::Point_3& p) { return {p.x(), p.y(), p.z()}; }
Vec3 vec(const Kernel::Vector_3& v) { return {v.x(), v.y(), v.z()}; }

// Per point: the normal of its neighbours' best plane and their spread off it.
struct LocalShape {
  std::vector<Vec3> normal;
  std::vector<double> spread;   // sqrt of the smallest eigenvalue, m
  std::vector<double> spacing;  // distance to the nearest other point, m
};

LocalShape local_shape(const std::vector<Vec3>& points) {
  using Point = Kernel::Point_3;
  using Base = CGAL::Search_traits_3<Kernel>;
  using Search = CGAL::Orthogonal_k_neighbor_search<Base>;
  std::vector<Point> pts;
  pts.reserve(points.size());
  for (const Vec3& p : points) pts.emplace_back(p.x(), p.y(), p.z());
  Search::Tree tree(pts.begin(), pts.end());
  LocalShape s;
  const unsigned k = unsigned(std::min<size_t>(kNeighbours, points.size()));
  for (const Point& q : pts) {
    Search search(tree, q, k);
    Vec3 mean = Vec3::Zero();
    std::vector<Vec3> nb;
    double nearest = 0;
    for (const auto& [p, d2] : search) {
      nb.push_back(vec(p));
      mean += nb.back();
      if (d2 > 0 && (nearest == 0 || d2 < nearest)) nearest = d2;
    }
    mean /= double(nb.size());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (const Vec3& p : nb) cov += (p - mean) * (p - mean).transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov / double(nb.size()));
    Vec3 n = eig.eigenvectors().col(0);
    s.normal.push_back(n.z() < 0 ? Vec3(-n) : n);
    // The plane takes 3 of the k degrees of freedom: the spread seen is short by k / (k - 3).
    s.spread.push_back(std::sqrt(std::max(0.0, eig.eigenvalues()(0)) * double(nb.size()) / double(nb.size() - 3)));
    s.spacing.push_back(std::sqrt(nearest));
  }
  return s;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + long(v.size() / 2), v.end());
  return v[v.size() / 2];
}

double plan_hull_area(const std::vector<Vec3>& points, const std::vector<int>& idx) {
  std::vector<Kernel::Point_2> in, hull;
  for (int i : idx) in.emplace_back(points[size_t(i)].x(), points[size_t(i)].y());
  CGAL::convex_hull_2(in.begin(), in.end(), std::back_inserter(hull));
  double a = 0;
  for (size_t i = 0; i < hull.size(); ++i) {
    const auto& p = hull[i];
    const auto& q = hull[(i + 1) % hull.size()];
    a += p.x() * q.y() - q.x() * p.y();
  }
  return std::abs(a) / 2;
}

std::vector<Vec3> subset(const std::vector<Vec3>& points, const std::vector<int>& idx) {
  std::vector<Vec3> out;
  out.reserve(idx.size());
  for (int i : idx) out.push_back(points[size_t(i)]);
  return out;
}

// The shapes RANSAC finds among `idx` of the points, with the factories asked for.
template <class... Shapes>
std::vector<std::unique_ptr<Primitive>> ransac(const std::vector<Vec3>& points, const LocalShape& local,
                                               const std::vector<int>& idx, double epsilon, double cluster,
                                               size_t min_points, unsigned seed) {
  PwnVector pwn;
  for (int i : idx) {
    const Vec3& p = points[size_t(i)];
    const Vec3& n = local.normal[size_t(i)];
    pwn.emplace_back(Kernel::Point_3(p.x(), p.y(), p.z()), Kernel::Vector_3(n.x(), n.y(), n.z()), i);
  }
  CGAL::get_default_random() = CGAL::Random(seed);
  Ransac r;
  r.set_input(pwn);
  (r.template add_shape_factory<Shapes>(), ...);
  Ransac::Parameters par;
  par.probability = 0.05;
  par.min_points = min_points;
  par.epsilon = epsilon;
  par.cluster_epsilon = cluster;
  par.normal_threshold = 0.8;
  r.detect(par);
  std::vector<std::unique_ptr<Primitive>> out;
  for (const auto& shape : r.shapes()) {
    auto p = std::make_unique<Primitive>();
    if (auto* c = dynamic_cast<CGAL::Shape_detection::Cylinder<Traits>*>(shape.get())) {
      p->kind = PrimitiveKind::Cylinder;
      p->point = vec(c->axis().point(0));
      p->axis = vec(c->axis().to_vector()).normalized();
      p->radius = c->radius();
    } else if (auto* s = dynamic_cast<CGAL::Shape_detection::Sphere<Traits>*>(shape.get())) {
      p->kind = PrimitiveKind::Sphere;
      p->point = vec(s->center());
      p->radius = s->radius();
    } else if (auto* k = dynamic_cast<CGAL::Shape_detection::Cone<Traits>*>(shape.get())) {
      p->kind = PrimitiveKind::Cone;
      p->point = vec(k->apex());
      p->axis = vec(k->axis()).normalized();
      p->angle = k->angle();
    } else if (auto* pl = dynamic_cast<CGAL::Shape_detection::Plane<Traits>*>(shape.get())) {
      p->kind = PrimitiveKind::Plane;
      p->axis = vec(pl->plane_normal()).normalized();
      p->point = vec(std::get<0>(pwn[shape->indices_of_assigned_points().front()]));
    }
    for (std::size_t j : shape->indices_of_assigned_points()) p->inliers.push_back(std::get<2>(pwn[j]));
    out.push_back(std::move(p));
  }
  return out;
}

// A cone this slender is a cylinder RANSAC happened to sample as a cone (a
// vault's points fit both); the cylinder has one parameter fewer.
constexpr double kCylinderLikeCone = 5 * kPi / 180;

Primitive as_cylinder(const Primitive& cone, const std::vector<Vec3>& points) {
  Primitive c = cone;
  c.kind = PrimitiveKind::Cylinder;
  c.angle = 0;
  std::vector<double> r;
  for (int i : cone.inliers) {
    const Vec3 v = points[size_t(i)] - cone.point;
    r.push_back((v - v.dot(cone.axis) * cone.axis).norm());
  }
  std::nth_element(r.begin(), r.begin() + long(r.size() / 2), r.end());
  c.radius = r[r.size() / 2];
  return c;
}

double sum_squares(const Primitive& s, const std::vector<Vec3>& points, const std::vector<int>& idx) {
  double rss = 0;
  for (int i : idx) rss += std::pow(s.distance(points[size_t(i)]), 2);
  return rss;
}

// Why a refitted curved shape cannot be a roof ("" when it can): a radius
// no roof has, a bowl instead of a dome, an upright cylinder (a wall), a cone
// not standing on its base.
std::string implausible(const Primitive& s, const std::vector<Vec3>& points) {
  double top = -1e300;
  for (int i : s.inliers) top = std::max(top, points[size_t(i)].z());
  const double tilt = std::acos(std::min(1.0, std::abs(s.axis.z()))) * 180 / kPi;
  char why[120] = "";
  if (s.kind != PrimitiveKind::Cone && (s.radius < 1 || s.radius > 200))
    std::snprintf(why, sizeof why, "radius %.2f m", s.radius);
  else if (s.kind == PrimitiveKind::Sphere && s.point.z() > top)
    std::snprintf(why, sizeof why, "a bowl (centre above its points)");
  else if (s.kind == PrimitiveKind::Cylinder && tilt < 60)
    std::snprintf(why, sizeof why, "axis %.0f deg from upright: a wall, not a vault", tilt);
  else if (s.kind == PrimitiveKind::Cone &&
           (tilt > 20 || s.point.z() < top - 0.5 || s.angle < 10 * kPi / 180 || s.angle > 80 * kPi / 180))
    std::snprintf(why, sizeof why, "a cone not standing on its base (axis %.0f deg, half-angle %.0f deg)", tilt,
                  s.angle * 180 / kPi);
  return why;
}

// Planes' account of the same points: the planes RANSAC finds among them at
// the same tolerance and their one best plane, each point taken by its
// nearest plane however far.
PlanarAccount planes_found(const std::vector<Vec3>& points, const LocalShape& local, const std::vector<int>& idx,
                           double epsilon, double cluster, unsigned seed) {
  const size_t min_points = std::max<size_t>(10, idx.size() / 50);
  auto found = ransac<CGAL::Shape_detection::Plane<Traits>>(points, local, idx, epsilon, cluster, min_points, seed);
  Primitive one;  // the points' one best plane is among the planes
  one.inliers = idx;
  found.push_back(std::make_unique<Primitive>(refit(one, subset(points, idx))));
  double rss = 0;
  for (int i : idx) {
    double best = 1e300;
    for (const auto& p : found) best = std::min(best, std::abs(p->distance(points[size_t(i)])));
    rss += best * best;
  }
  return {std::sqrt(rss / double(idx.size())), int(found.size())};
}

}  // namespace

double bow(const std::vector<Vec3>& points, const std::vector<int>& idx) {
  Primitive one;
  one.inliers = idx;
  const Primitive plane = refit(one, subset(points, idx));
  return std::sqrt(sum_squares(plane, points, idx) / double(idx.size()));
}

double bic(double rmse, int parameters, double n, double noise) {
  return n * (rmse * rmse) / (noise * noise) + parameters * std::log(n);
}

namespace {

// Why planes serve as well as curved candidate `p` ("" when they do not): its
// BIC must beat that of every planar account by kBicMargin, its patch must
// bow away from flat by kMinBowOverFit times its own RMS and kMinBowM at least
// (a patch a few cm off flat is a plane whatever fits it best), and it must
// fit its points to within kMaxFitOverNoise times the noise.
std::string planes_do_as_well(Primitive& p, const std::vector<PlanarAccount>& planar, double noise) {
  char why[160] = "";
  const double n = double(p.inliers.size()), curved = bic(p.rmse, parameters(p.kind), n, noise);
  for (const PlanarAccount& a : planar) {
    const double flat = bic(a.rmse, 3 * a.planes, n, noise);
    if (p.planes == 0 || flat < bic(p.planar_rmse, 3 * p.planes, n, noise)) p.planar_rmse = a.rmse, p.planes = a.planes;
    if (curved + kBicMargin >= flat && !*why)
      std::snprintf(why, sizeof why, "%d planes at %.3f m do as well as the %s at %.3f m (BIC %.0f, %.0f)", a.planes,
                    a.rmse, to_string(p.kind), p.rmse, flat, curved);
  }
  if (!*why && (p.bow < kMinBowM || p.bow < kMinBowOverFit * p.rmse))
    std::snprintf(why, sizeof why, "nearly flat: %.3f m off its best plane, fitted to %.3f m", p.bow, p.rmse);
  if (!*why && p.rmse > kMaxFitOverNoise * noise)
    std::snprintf(why, sizeof why, "fits its points to %.3f m, the scan's noise is %.3f m", p.rmse, noise);
  return why;
}

struct Tolerances {
  double epsilon, cluster, min_plan_area;
  unsigned seed;
  double noise;
  const std::function<PlanarAccount(const std::vector<Vec3>&)>& planar_model;
};

// Refits candidate `p` and says why it is no roof surface better than planes
// ("" when it is). The cheap tests first: most candidates on planar roofs
// barely bow.
std::string judge(Primitive& p, const std::vector<Vec3>& points, const LocalShape& local, const Tolerances& tol) {
  p.bow = bow(points, p.inliers);
  char flat[80];
  std::snprintf(flat, sizeof flat, "nearly flat: %.3f m off its best plane", p.bow);
  if (p.bow < kMinBowM) return flat;
  const std::vector<int> inliers = p.inliers;
  p = refit(p, subset(points, inliers));
  p.inliers = inliers;
  if (p.kind == PrimitiveKind::Cone && p.angle < kCylinderLikeCone) {
    p = refit(as_cylinder(p, points), subset(points, inliers));
    p.inliers = inliers;
  }
  p.rmse = std::sqrt(sum_squares(p, points, inliers) / double(inliers.size()));
  std::string why = implausible(p, points);
  if (why.empty() && plan_hull_area(points, inliers) < tol.min_plan_area)
    why = "covers under " + std::to_string(int(tol.min_plan_area)) + " m2";
  if (!why.empty()) return why;
  std::vector<PlanarAccount> planar{planes_found(points, local, inliers, tol.epsilon, tol.cluster, tol.seed)};
  if (tol.planar_model) planar.push_back(tol.planar_model(subset(points, inliers)));
  return planes_do_as_well(p, planar, tol.noise);
}

// The percentage of `points` within `epsilon` of p. Not its RANSAC inliers:
// the search gives each point to one shape, and a vault whose crown a second,
// rejected cylinder took held 89 % of a roof it lies on 98 % of.
int share_on(const Primitive& p, const std::vector<Vec3>& points, double epsilon) {
  const auto on = std::count_if(points.begin(), points.end(), [&](const Vec3& q) { return std::abs(p.distance(q)) <= epsilon; });
  return int(std::lround(100.0 * double(on) / double(points.size())));
}

// Whether a and b are one surface: each within `epsilon` (RMS) of the other's
// inliers. RANSAC gives each point to one shape, so one vault can come back
// as two cylinders that share its points out between them.
bool same_surface(const Primitive& a, const Primitive& b, const std::vector<Vec3>& points, double epsilon) {
  const auto rms = [&](const Primitive& s, const Primitive& on) {
    return std::sqrt(sum_squares(s, points, on.inliers) / double(on.inliers.size()));
  };
  return a.kind == b.kind && rms(a, b) <= epsilon && rms(b, a) <= epsilon;
}

// Of the kept surfaces that are one (same_surface), the one on the larger
// share stays; the others go to the rejected with the reason.
void drop_repeats(PrimitiveFit& fit, const std::vector<Vec3>& points, double epsilon) {
  std::vector<Primitive> kept;
  for (Primitive& p : fit.curved) {
    const auto twin = std::find_if(kept.begin(), kept.end(),
                                   [&](const Primitive& k) { return same_surface(k, p, points, epsilon); });
    if (twin == kept.end()) {
      kept.push_back(std::move(p));
      continue;
    }
    if (p.share > twin->share) std::swap(p, *twin);
    fit.why_rejected.push_back("the same surface as the " + twin->describe() + ", on more of the points");
    fit.rejected.push_back(std::move(p));
  }
  fit.curved = std::move(kept);
}

}  // namespace

const char* to_string(PrimitiveKind k) {
  switch (k) {
    case PrimitiveKind::Plane: return "plane";
    case PrimitiveKind::Cylinder: return "cylinder";
    case PrimitiveKind::Sphere: return "sphere";
    case PrimitiveKind::Cone: return "cone";
  }
  return "?";
}

int parameters(PrimitiveKind k) {
  switch (k) {
    case PrimitiveKind::Plane: return 3;
    case PrimitiveKind::Sphere: return 4;
    case PrimitiveKind::Cylinder: return 5;
    case PrimitiveKind::Cone: return 6;
  }
  return 0;
}

std::optional<CurvedPrimitive> snap_target(const Primitive& p) {
  CurvedPrimitive c;
  switch (p.kind) {
    case PrimitiveKind::Plane: return std::nullopt;
    case PrimitiveKind::Sphere: c.kind = CurvedPrimitive::Kind::Sphere; break;
    case PrimitiveKind::Cylinder: c.kind = CurvedPrimitive::Kind::Cylinder; break;
    case PrimitiveKind::Cone: c.kind = CurvedPrimitive::Kind::Cone; break;
  }
  c.point = p.point, c.axis = p.axis, c.radius = p.radius, c.angle = p.angle;
  return c;
}

double Primitive::distance(const Vec3& p) const {
  const Vec3 v = p - point;
  switch (kind) {
    case PrimitiveKind::Plane: return v.dot(axis);
    case PrimitiveKind::Sphere: return v.norm() - radius;
    case PrimitiveKind::Cylinder: return (v - v.dot(axis) * axis).norm() - radius;
    case PrimitiveKind::Cone: {
      const double h = v.dot(axis), q = (v - h * axis).norm();
      return q * std::cos(angle) - h * std::sin(angle);
    }
  }
  return 0;
}

std::string Primitive::describe() const {
  char s[160];
  switch (kind) {
    case PrimitiveKind::Plane:
      std::snprintf(s, sizeof s, "plane, normal %.2f %.2f %.2f", axis.x(), axis.y(), axis.z());
      break;
    case PrimitiveKind::Sphere: std::snprintf(s, sizeof s, "sphere r %.2f m", radius); break;
    case PrimitiveKind::Cylinder:
      std::snprintf(s, sizeof s, "cylinder r %.2f m, axis %.2f %.2f %.2f", radius, axis.x(), axis.y(), axis.z());
      break;
    case PrimitiveKind::Cone: std::snprintf(s, sizeof s, "cone, half-angle %.1f deg", angle * 180 / kPi); break;
  }
  if (rmse == 0) return s;
  char fits[120];
  std::snprintf(fits, sizeof fits, ", fit %.3f m, planes %.3f m, bow %.3f m", rmse, planar_rmse, bow);
  return s + std::string(fits);
}

double estimate_noise(const std::vector<Vec3>& points) {
  if (points.size() < size_t(kNeighbours)) return 0;
  return median(local_shape(points).spread);
}

PrimitiveFit find_curved_surfaces(const std::vector<Vec3>& all_points, const PrimitiveSearch& search) {
  PrimitiveFit fit;
  if (all_points.size() < size_t(kNeighbours) * 2) return fit;
  // A large roof is searched on every k-th point: kMaxPoints fix a vault's radius to millimetres.
  const size_t stride = (all_points.size() + kMaxPoints - 1) / kMaxPoints;
  std::vector<int> kept;
  for (size_t i = 0; i < all_points.size(); i += stride) kept.push_back(int(i));
  const std::vector<Vec3> points = subset(all_points, kept);
  const LocalShape local = local_shape(points);
  const double spacing = std::max(0.01, median(local.spacing));
  fit.noise = search.noise > 0 ? search.noise : std::max(0.005, median(local.spread));
  const Tolerances tol{2.5 * fit.noise, 4 * spacing, search.min_plan_area, search.seed, fit.noise, search.planar_model};
  const size_t min_points = std::max<size_t>(30, size_t(0.5 * search.min_plan_area / (spacing * spacing)));
  std::vector<int> all(points.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = int(i);
  using namespace CGAL::Shape_detection;
  auto shapes = ransac<Plane<Traits>, Cylinder<Traits>, Sphere<Traits>, Cone<Traits>>(
      points, local, all, tol.epsilon, tol.cluster, min_points, search.seed);
  for (auto& s : shapes) {
    if (s->kind == PrimitiveKind::Plane) continue;
    if (s->kind == PrimitiveKind::Cone && s->angle < kCylinderLikeCone) *s = as_cylinder(*s, points);
    Primitive p = *s;
    const std::string why = judge(p, points, local, tol);
    p.share = share_on(p, points, tol.epsilon);
    if (why.empty()) {
      fit.curved.push_back(std::move(p));
    } else {
      fit.rejected.push_back(std::move(p));
      fit.why_rejected.push_back(why);
    }
  }
  drop_repeats(fit, points, tol.epsilon);
  for (std::vector<Primitive>* found : {&fit.curved, &fit.rejected})
    for (Primitive& p : *found)
      for (int& i : p.inliers) i = kept[size_t(i)];  // indices into the points given
  return fit;
}

}  // namespace c3d
