#pragma once
// Curved roofs in the parcel's models (docs/curved.md): a building whose
// roof is held by one cylinder, sphere or cone, or by one surface of
// revolution, is modelled on that surface, and a flat roof carrying domes
// or cones on them; one with a curved surface that cannot be (a curved part
// of a pitched roof) keeps its planar model, and the parcel is told why its
// areas are unreliable.
#include <string>
#include <vector>

#include "core/types.h"

namespace c3d {

// `b` (its planar model) modelled again on the curved surface that holds at
// least kWholeRoofShare of `own` (its roof points), if that model is valid;
// the surface's points are then taken from `nearby` (the parcel's roof
// points), which holds the steep flanks planar segmentation may leave out,
// and `walls` (the parcel's wall points) place the walls they see.
// A roof that is a free-form surface of revolution (an onion dome) is
// modelled on it likewise. Returns why the parcel is `suspect` ("" when it
// is not): a curved surface the planar model stands for, or a drum no wall
// point shows under a roof that may overhang it.
std::string model_curved_roof(Building& b, const std::vector<Vec3>& own, const std::vector<Vec3>& nearby,
                              const std::vector<Vec3>& walls, double spacing, double storey_height);

// The share of a building's roof points one surface must hold to be its roof.
constexpr int kWholeRoofShare = 90;

}  // namespace c3d
