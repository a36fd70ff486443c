#pragma once
// Surfaces beyond planes in a building's roof points. CGAL's Efficient
// RANSAC (plane, cylinder, sphere, cone) finds candidate shapes; each curved
// one is refitted by least squares and kept only where it explains its points
// better than planes do, by the Bayesian information criterion with the
// points' own noise (docs/curved.md, "Which surface").
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/optimizer/optimizer.h"
#include "core/types.h"

namespace c3d {

enum class PrimitiveKind { Plane, Cylinder, Sphere, Cone };
const char* to_string(PrimitiveKind k);

struct Primitive {
  PrimitiveKind kind = PrimitiveKind::Plane;
  Vec3 point = Vec3::Zero();  // plane: on it; cylinder: on the axis; sphere: centre; cone: apex
  Vec3 axis = Vec3::UnitZ();  // plane: normal; cylinder, cone: axis (unit); sphere: unused
  double radius = 0;          // cylinder, sphere
  double angle = 0;           // cone: half-angle at the apex, rad
  std::vector<int> inliers;   // indices into the points searched (every k-th of a large set)
  int share = 0;  // percent of the points searched that lie on it (within the search tolerance)
  double rmse = 0;            // of the inliers' distances to the surface, m
  // The planar account that competes with it best (by the criterion): the
  // RMS distance of the inliers to those planes and how many planes that takes.
  double planar_rmse = 0;
  int planes = 0;
  double bow = 0;             // RMS distance of the inliers to their one best plane, m
  // Signed distance of p to the surface (outside / above positive).
  double distance(const Vec3& p) const;
  // "sphere r 5.02 m", "cylinder r 4.10 m, axis 0.00 1.00 0.02", ...
  std::string describe() const;
};

// A sphere, cylinder or cone as the optimizer snaps onto it; nullopt for a plane.
std::optional<CurvedPrimitive> snap_target(const Primitive& p);

// How well planes explain some points: the RMS distance to the nearest of
// them and how many of them it takes.
struct PlanarAccount {
  double rmse = 0;
  int planes = 0;
};

struct PrimitiveSearch {
  double noise = 0;    // sigma of the points about their surface, m; 0: estimated from them
  double min_plan_area = 8;  // m2 of roof a curved surface must cover to count
  unsigned seed = 1;   // RANSAC's draws: the same points give the same surfaces
  // The planar model a curved surface competes with (a building's modelled
  // roof) on given points; the planes RANSAC finds among them compete too.
  std::function<PlanarAccount(const std::vector<Vec3>&)> planar_model;
};

// What a curved surface must do better than planes. A BIC lower by 10 is
// "very strong" evidence on Kass and Raftery's scale (1995); a patch a few
// cm off flat is a plane whatever fits it best (on the AHN3 town no
// candidate passed, docs/curved.md).
constexpr double kBicMargin = 10, kMinBowM = 0.15;
// A curved surface bows kMinBowOverFit times its RMS from its points at
// least: on the curved sample towns the kept surfaces bow 7-48 times.
constexpr double kMinBowOverFit = 5;
// A roof surface explains its points to the scan's noise: a curved surface
// fitting a textured or broken planar roof a little better than its planes
// still leaves them farther (Cimahi: 1.8 times).
constexpr double kMaxFitOverNoise = 1.5;

// Bayesian information criterion of a model with `parameters` leaving n
// points at `rmse` when their noise is `noise`.
double bic(double rmse, int parameters, double n, double noise);
// The parameters a surface of kind k takes (a plane 3, a sphere 4, a
// cylinder 5, a cone 6).
int parameters(PrimitiveKind k);

// What the search found in one set of points.
struct PrimitiveFit {
  double noise = 0;                // the noise used (given or estimated), m
  std::vector<Primitive> curved;   // kept: better than planes by the criterion
  std::vector<Primitive> rejected; // curved candidates planes explain as well
  std::vector<std::string> why_rejected;  // in step with `rejected`
};

// The curved surfaces among `points` (a building's roof points, local
// coordinates). Deterministic for a given seed.
PrimitiveFit find_curved_surfaces(const std::vector<Vec3>& points, const PrimitiveSearch& search);

// RMS distance of points[idx] to their one best plane: how far the surface
// they lie on bows away from flat.
double bow(const std::vector<Vec3>& points, const std::vector<int>& idx);

// The points' noise about their surface: from each point's 16 nearest
// neighbours, the spread off their best plane, median over the points.
double estimate_noise(const std::vector<Vec3>& points);

}  // namespace c3d
