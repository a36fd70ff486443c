#pragma once
// A roof that is a surface of revolution about a vertical axis with a free
// profile: an onion dome, a bell or ogee dome, a curved spire
// (docs/curved.md, "Free-form domes"). Seen from a pole on its axis at the
// height of its lowest roof points, the surface lies at a distance d(theta)
// for each elevation angle theta: a B-spline, OpenCASCADE's approximation of
// the points' medians in even steps of theta. The axis stands where that
// profile explains the points best.
#include <optional>
#include <string>
#include <vector>

#include "core/primitives/revolution_faces.h"
#include "core/types.h"

namespace c3d {

struct RevolvedRoof {
  Vec2 axis = Vec2::Zero();   // plan position of the vertical axis
  std::vector<Vec2> profile;  // (rho, z), dense: from the widest ring seen from the air up to the apex (rho 0)
  std::vector<int> inliers;   // the points within 2.5 noise of it (indices)
  double rmse = 0;            // of the inliers' distances to the surface, m
  int parameters = 0;         // the B-spline's poles, the axis and the pole (3)
  // "surface of revolution, widest r 4.31 m, 15 parameters, fit 0.031 m"
  std::string describe() const;
  // Whether the roof is steeper than 60 deg where the points stop: it may
  // curve back in over a narrower drum (an onion's bulge), plumb at its
  // widest ring, which the spline's first steps read shallower.
  bool may_overhang() const;
};

// The surface of revolution through `points` (a building's roof points,
// local) about a vertical axis near `axis_guess`; none where the points do
// not go round it (fewer than 50, or no profile OpenCASCADE can fit).
std::optional<RevolvedRoof> fit_revolved_roof(const std::vector<Vec3>& points, const Vec2& axis_guess,
                                              double noise);

struct RevolvedBuildingInput {
  std::string building_id;
  RevolvedRoof roof;
  std::vector<Vec3> wall_points;  // the parcel's: they place the drum and its top where a wall scan saw them
  double ground_z = 0;
  double spacing = 0.2;           // typical point spacing in plan, m
  double chord = kModelChordM;    // largest distance of the tessellation from the surface, m
};

// The building on a round drum: the roof is the surface seen from the air,
// and where the drum the wall scan saw stands inside the roof's widest ring,
// the bulge's underside (unseen from the air) as the straight band from the
// drum's top to that ring. Elements [roof, drum wall, ground], sigma_area
// from moving the widest ring and the drum by half a point spacing.
std::optional<Building> revolved_roof_building(const RevolvedBuildingInput& in);

// Whether a wall scan saw the drum (at least kMinWallPoints around a quarter
// of it); without it the drum stands under the widest ring.
bool drum_seen(const RevolvedBuildingInput& in);

}  // namespace c3d
