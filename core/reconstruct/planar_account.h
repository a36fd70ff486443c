#pragma once
// How a building's modelled roof planes explain some points: the planar
// rival every curved surface must beat (docs/curved.md).
#include <map>
#include <utility>
#include <vector>

#include "core/evaluate/evaluate.h"
#include "core/primitives/primitives.h"
#include "core/types.h"

namespace c3d {

// The building's roof faces, each tagged with its roof element (a plane),
// and each element's plane (unit normal, offset).
struct RoofPlanes {
  FaceIndex faces;
  std::map<int, std::pair<Vec3, double>> plane;
};

RoofPlanes roof_planes(const Building& b);

// Their RMS distance to the nearest roof face, and how many planes take at
// least 2 % of them. A point beyond the roof's plan (no face above or below
// it) is measured to the plane of its nearest face: the outline, not the
// surface, left it out, and an outline's error must not pass for the
// planes' (a gable whose corner the outline cut off would look curved).
PlanarAccount planar_account(const RoofPlanes& roof, const std::vector<Vec3>& pts);

}  // namespace c3d
