#pragma once
// A building whose whole roof is one curved surface, modelled on that
// surface: a barrel vault on a rectangular hall (or springing from the
// ground: end walls only), a dome or a cone on a round drum. The roof is the
// surface itself inside the footprint, tessellated within a chord tolerance;
// walls rise from the ground floor to it; the footprint comes from the
// surface's own points (docs/curved.md, "Curved buildings").
#include <optional>
#include <string>
#include <vector>

#include "core/primitives/primitives.h"
#include "core/types.h"

namespace c3d {

struct CurvedBuildingInput {
  std::string building_id;
  Primitive roof;                // a cylinder with a level axis, a sphere or a cone standing upright
  std::vector<Vec3> roof_points; // the points it explains (local coordinates)
  std::vector<Vec3> wall_points; // wall points near it, if any: they place the walls where they see them
  double ground_z = 0;           // ground floor level (local)
  double spacing = 0.2;          // typical point spacing in plan, m
  double chord = 0.01;           // largest distance of the tessellation from the surface, m
};

// The building, elements measured on its faces (area within the chord of the
// surface's), with sigma_area from moving its rim by its uncertainty; none when
// the surface cannot stand on a footprint (a sphere whose rim would lie below
// the ground, a cylinder whose axis is not level).
std::optional<Building> curved_building(const CurvedBuildingInput& in);

}  // namespace c3d
