#pragma once
// Classifying a cloud: terrain under it, features in a local frame, the forest's
// classes, and the classes written back as the pipeline's own codes, so that a
// classified cloud goes through `batch` as any classified cloud does.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/classify/forest.h"
#include "core/types.h"

namespace c3d {

// The code written for PointClass::Other: ASPRS "unclassified", which no class
// mapping takes as roof, wall or ground.
constexpr std::uint8_t kOtherClassCode = 1;

// The terrain under a cloud when no DTM is given: the ground-class points'
// lowest z per 1 m cell (as the batch builds its DTM); without ground points
// the simple morphological filter's terrain (ground_filter.h: on IGN's
// unclassified tile 77050_627760 it lifted ground recall from 0.54 to 0.97, where the
// lowest points of coarse cells had left flat ground under roof height).
// note says which.
Dtm terrain_from_cloud(const PointCloud& cloud, const ClassMapping& classes, std::string* note);

// Height of every point above the terrain; points outside the grid use its
// nearest edge.
std::vector<double> heights_above_terrain(const std::vector<Vec3>& world, const Dtm& terrain);

// Features of a cloud in world coordinates (computed in a local frame), with its
// return fields where it has them.
FeatureTable cloud_features(const PointCloud& cloud, const Dtm& terrain);

struct Classification {
  std::vector<PointClass> classes;                // one per point
  std::array<long, kPointClassCount> counts{};   // per PointClass
};
Classification classify_points(const PointForest& forest, const PointCloud& cloud, const Dtm& terrain);

// The class code written for each PointClass: the mapping's first ground, roof
// and wall codes, kOtherClassCode for other.
std::uint8_t class_code(PointClass c, const ClassMapping& classes);
// Replaces cloud.classes by the codes of the given classes.
void write_classes(PointCloud& cloud, const std::vector<PointClass>& classes, const ClassMapping& mapping);

}  // namespace c3d
