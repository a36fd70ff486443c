#pragma once
// What `evaluate` measures, sorted out of its inputs: a model's faces as roof
// or wall, a CityJSON model as mesh groups, and a cloud's roof and wall points.
#include <string>
#include <vector>

#include "core/io/mesh_io.h"
#include "core/types.h"

namespace c3d {

enum class SurfaceKind { Roof, Wall, Other };

// Roof or wall by the group/material label an exporter gives, else by the normal
// (upward-facing and below 80 deg slope: roof; near vertical: wall).
SurfaceKind surface_kind(const MeshGroup& group, const Face& face);

// A model's buildings as mesh groups in world coordinates, one per element,
// named "<parcel id>_<building id>_<element type>" (the parcel from the
// building's parcel_id, where it has one), so that each element is measured for
// its own parcel, as the batch's OBJ groups are.
std::vector<MeshGroup> element_groups(const BatchModel& model);

// "roof=6,wall=64" (a kind may repeat: roof=6,roof=7); ground keeps its default.
// Throws InputError(where, …) on an item that is not roof=code or wall=code.
ClassMapping parse_class_codes(const std::string& text, const std::string& where);

// The cloud's points of the roof and of the wall classes, in cloud order, one
// per place (one_per_place: copies of a point count once, as in the batch). A
// cloud without classes is taken as roof points only.
struct RoofWallPoints {
  std::vector<Vec3> roof, wall;
  bool unclassified = false;  // the cloud had no classes
};
RoofWallPoints roof_and_wall_points(const PointCloud& cloud, const ClassMapping& classes);

}  // namespace c3d
