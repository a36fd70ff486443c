#pragma once
// Geometry validation of building solids and element faces, following ISO 19107
// as val3dity applies it; issues carry val3dity's error codes.
#include <string>
#include <vector>

#include "core/check/polygon_rules.h"
#include "core/types.h"

namespace c3d {

const char* val3dity_name(int code);

struct ValidationIssue {
  std::string building_id;
  int code = 0;
  std::string where;    // "solid face 3", "element 2 (roof) face 0", "solid"
  std::string message;  // human-readable detail
};

using ValidationOptions = PolygonRules;  // snap, planarity and normals tolerances

std::vector<ValidationIssue> validate_building(const Building& b,
                                               const ValidationOptions& opt = {});
std::vector<ValidationIssue> validate_model(const BatchModel& model,
                                            const ValidationOptions& opt = {});
// "<building>: <code> <NAME> at <where>: <message>"
std::string to_string(const ValidationIssue& issue);

}  // namespace c3d
