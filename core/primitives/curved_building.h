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
#include "core/primitives/revolution_faces.h"
#include "core/types.h"

namespace c3d {

struct CurvedBuildingInput {
  std::string building_id;
  Primitive roof;                // a cylinder with a level axis, a sphere or a cone standing upright
  std::vector<Vec3> roof_points; // the points it explains (local coordinates)
  std::vector<Vec3> wall_points; // wall points near it, if any: they place the walls where they see them
  double ground_z = 0;           // ground floor level (local)
  double ground_sigma = 0;       // its standard error, m (the terrain model's, envelope::kTerrainSigma)
  double spacing = 0.2;          // typical point spacing in plan, m
  double chord = kModelChordM;   // largest distance of the tessellation from the surface, m
};

// The building, elements measured on its faces (area within the chord of the
// surface's), with sigma_area from moving its rim by its uncertainty; none when
// the surface cannot stand on a footprint (a sphere whose rim would lie below
// the ground, a cylinder whose axis is not level).
std::optional<Building> curved_building(const CurvedBuildingInput& in);

// A flat roof carrying domes or cones (a mosque's hall, a church's crossing):
// the footprint's prism up to the flat roof, each cap rising from it (or
// from a drum on it where its rim stands at least kMinDrumM above it).
struct DomedRoofInput {
  std::string building_id;
  Polygon2 footprint;                         // the hall's, from its planar model
  Polygon2 roof_outline;                      // the flat roof's, overhang included; empty: the footprint
  double ground_z = 0, roof_z = 0;            // ground floor and flat roof levels (local)
  std::vector<Primitive> caps;                // spheres, cones standing upright
  std::vector<std::vector<Vec3>> cap_points;  // the points each explains, in step with caps
  double spacing = 0.2;
  double chord = kModelChordM;
};
constexpr double kMinDrumM = 0.3;

// The building: elements [flat roof, each cap, each drum, one wall per
// footprint edge (outer ring, then holes), ground, outer ceiling where the
// roof outline reaches past the footprint], caps' sigma_area from
// moving their rims as curved_building's; none when a cap does not stand on
// the flat roof inside the footprint clear of the others.
std::optional<Building> domed_roof_building(const DomedRoofInput& in);

}  // namespace c3d
