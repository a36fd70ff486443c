#pragma once
// Faces of a surface of revolution about a vertical axis, shared by the
// curved buildings: rings of planar trapezoids from its rim up to its apex,
// and what every curved building is assembled with.
#include <cstddef>
#include <string>
#include <vector>

#include "core/primitives/primitives.h"
#include "core/types.h"

namespace c3d {

struct RevolvedFaces {
  std::vector<Face> roof;  // facing out and up
  Ring3 rim;               // the lowest ring, counter-clockwise in plan
};

// The surface through `profile`, (rho, z) from the rim (first) to the apex
// (last, rho 0), with n steps around the axis at plan position `axis`.
// Ring vertices are computed one way only, so a drum or a flat roof built on
// the rim shares them exactly.
RevolvedFaces revolution_faces(const Vec2& axis, const std::vector<Vec2>& profile, int n);

// The drum under a rim (counter-clockwise in plan), down to `floor_z`.
std::vector<Face> drum_faces(const Ring3& rim, double floor_z);

// An element of these faces, measured on them (area, plan area).
Element element_of(ElementType type, std::vector<Face> faces);

// A round building's elements: the roof, the drum under its rim down to
// ground_z where the rim stands at least min_wall above it, the ground disc.
Building on_round_drum(RevolvedFaces roof, double ground_z, double min_wall);

// Marks a wall element as placed by `points` wall points (measured), or,
// with none, as standing plumb under the roof's edge (default).
void mark_wall(Element& wall, int points);
// Every wall of `b` so.
void mark_walls(Building& b, int points);

// The exact part of a round building (ExactShape): its profile (rho, z)
// turned about the vertical axis at `axis`, out along the floor at floor_z
// to the rim's radius, up to the rim, then along `roof` to the apex on the
// axis.
ShapePart round_part(const Vec2& axis, double floor_z, const Vec2& rim, std::vector<ProfileStep> roof);

// The exact part of a hall: its footprint's outer ring swept up from
// ground_z to top_z.
ShapePart hall_part(const Ring2& outer, double ground_z, double top_z);

// A footprint's rings as walls need them: outer counter-clockwise, holes
// clockwise.
Polygon2 oriented(Polygon2 p);
// A plan ring at height z.
Ring3 lifted(const Ring2& r, double z);
// A plan polygon lifted to height z, facing up or down.
Face face_at(const Polygon2& p, double z, bool up);

// b's solid made of all its elements' faces so far, its id, ground level and
// LoD 2.2: what every curved building ends with.
void close_curved(Building& b, const std::string& id, double ground_z);

// What the curved builders share (docs/curved.md): a wall lower than
// kMinWallM under a rim is no wall (the roof meets the ground); a rim is
// placed from the kRimQuantile of the points (seen from the air they lie
// evenly over the plan); wall points within kWallReachM of a wall count for
// it, and kMinWallPoints of them place it instead.
constexpr double kMinWallM = 0.05;
constexpr double kRimQuantile = 0.95;
constexpr double kWallReachM = 0.5;
constexpr size_t kMinWallPoints = 30;

// The largest distance of a curved building's faces from its surface (a
// ring of chords of sagitta s leaves its disc 1.3 s / r short: 0.3 % at
// 5 m; the volume is taken from the exact shape, exact_solid.h).
constexpr double kModelChordM = 0.01;

// Steps that keep an arc of `radius` over `angle` within `chord` of its
// chords (at least 8).
int arc_steps(double radius, double angle, double chord);

// Areas are measured on a tessellation this many times finer than the
// faces': the chords' shortfall (up to 0.3 % of a drum's disc) is then under
// a hundredth of it, well below any sigma.
constexpr double kMeasureFiner = 100;
// b's elements take the areas and plan areas of `fine`, the same building
// tessellated kMeasureFiner times finer (same elements, same order), and are
// marked measured on the surface.
void take_surface_areas(const Building& fine, Building& b);

// q-quantile of v (0 <= q <= 1).
double quantile(std::vector<double> v, double q);
// The top of heights spread evenly up a wall (a drum's wall points): from
// their 2 and 98 % quantiles.
double spread_top(std::vector<double> z);
// Standard error of a kRimQuantile-quantile of n values spread evenly over
// a range of 1 (its variance q (1 - q) / n over the density squared).
double quantile_se(size_t n);

// Height of a sphere or a cone standing on its base at plan distance rho
// from its axis.
double revolved_z(const Primitive& p, double rho);
// A sphere's or cone's surface from radius r in to its axis (rings evenly
// in polar angle on a sphere; a cone needs none between rim and apex).
RevolvedFaces cap_faces(const Primitive& p, double r, double chord);
// The exact curve of a sphere's or cone's profile from radius r in to its
// apex on the axis.
std::vector<ProfileStep> cap_curve(const Primitive& p, double r);

}  // namespace c3d
