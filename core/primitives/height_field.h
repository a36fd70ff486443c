#pragma once
// A free-form roof: a smooth surface that turns about no axis (a saddle, a
// wave, a shell), as a B-spline height field z = f(x, y): the roof points
// fitted by least squares on cubic B-splines with even knots, a light
// penalty on the poles' second differences for the poles no point speaks
// for (P-splines), the knots' spacing chosen by the Bayesian information
// criterion. OpenCASCADE holds and evaluates the surface (docs/curved.md,
// "Free-form roofs").
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/primitives/revolution_faces.h"
#include "core/types.h"

namespace c3d {

struct HeightFieldRoof {
  SplineSurface surface;     // local coordinates; u = x, v = y
  std::vector<int> inliers;  // the points within 2.5 noise of it (indices)
  double rmse = 0;           // of the inliers' distances to it, m
  int parameters = 0;        // its poles' heights
  // "B-spline height field, 9 x 7 poles, fit 0.031 m"
  std::string describe() const;
};

// The height field through `points` (a roof's, local) over their plan and
// `cover` (the footprint's ring), its parameters along `along` (the
// footprint's long side) and across; none where fewer than 50 points.
// `spacing`: the points' typical spacing in plan, m.
std::optional<HeightFieldRoof> fit_height_field(const std::vector<Vec3>& points, double noise, double spacing,
                                                const Ring2& cover, const Vec2& along);

// Height and slopes of a height field at plan points
// (OpenCASCADE evaluates it).
class HeightField {
 public:
  explicit HeightField(const SplineSurface& s);
  double z(const Vec2& q) const;
  Vec2 slope(const Vec2& q) const;  // dz/dx, dz/dy
  // Distance of p to the surface along its normal (to first order), signed: above positive.
  double distance(const Vec3& p) const;
  // The largest principal curvature over the box [lo, hi], sampled every `step` m.
  double max_curvature(const Vec2& lo, const Vec2& hi, double step) const;

 private:
  struct Surface;
  std::shared_ptr<const Surface> surface_;
};

struct FreeFormInput {
  std::string building_id;
  SplineSurface roof;
  Polygon2 footprint;           // the hall's, from its planar model
  double ground_z = 0;          // local
  // 1-sigma position of each footprint edge (outer ring, then holes), its
  // own part, and the shift all of them share, m (docs/accuracy.md).
  std::vector<double> edge_sigma;
  double common_sigma = 0;
  double chord = kModelChordM;  // largest distance of the roof's triangles from the surface, m
};

// The hall under its free-form roof: elements [roof, one wall per footprint
// edge (outer ring, then holes) up to the surface, ground]; the roof's
// triangles within `chord` of the surface, its sigma_area from moving the
// footprint's edges by their sigma. None where the footprint is not a
// polygon or the roof does not stand kMinWallM above the ground everywhere.
std::optional<Building> free_form_building(const FreeFormInput& in);

}  // namespace c3d
