#pragma once
// Curved roofs in the parcel's models (docs/curved.md): a building whose
// roof is held by one cylinder, sphere or cone is modelled on that surface;
// one with a curved surface that cannot be (a dome on a flat roof, a curved
// part of a larger roof) keeps its planar model, and the parcel is told why
// its areas are unreliable.
#include <string>
#include <vector>

#include "core/types.h"

namespace c3d {

// `b` (its planar model) modelled again on the curved surface that holds at
// least kWholeRoofShare of `own` (its roof points), if that model is valid;
// the surface's points are then taken from `nearby` (the parcel's roof
// points), which holds the steep flanks planar segmentation may leave out,
// and `walls` (the parcel's wall points) place the walls they see.
// Returns what the parcel's reason must say of a curved surface the planar
// model stands for ("" for none: no curved surface, or b now modelled on it).
std::string model_curved_roof(Building& b, const std::vector<Vec3>& own, const std::vector<Vec3>& nearby,
                              const std::vector<Vec3>& walls, double spacing, double storey_height);

// The share of a building's roof points one surface must hold to be its roof.
constexpr int kWholeRoofShare = 90;

}  // namespace c3d
