#pragma once
// Geometry validation of building solids and element faces, following ISO 19107
// as val3dity applies it; issues carry val3dity's error codes.
#include <string>
#include <vector>

#include "core/types.h"

namespace c3d {

// val3dity error codes used here.
enum Val3dityCode : int {
  kTooFewPoints = 101,
  kConsecutivePointsSame = 102,
  kRingSelfIntersection = 104,   // also: ring that touches itself, zero-area ring
  kNonPlanarDistancePlane = 203,
  kNonPlanarNormalsDeviation = 204,
  kTooFewPolygons = 301,
  kShellNotClosed = 302,
  kNonManifoldCase = 303,
  kMultipleConnectedComponents = 305,
  kShellSelfIntersection = 306,
  kPolygonWrongOrientation = 307,
};
const char* val3dity_name(int code);

struct ValidationIssue {
  std::string building_id;
  int code = 0;
  std::string where;    // "solid face 3", "element 2 (roof) face 0", "solid"
  std::string message;  // human-readable detail
};

struct ValidationOptions {
  double snap_tol = 0.001;       // vertices closer than this are one vertex (m)
  double planarity_tol = 0.01;   // max distance to the fitted plane (m)
  double normals_tol_deg = 20;   // max triangle-normal deviation (204)
};

std::vector<ValidationIssue> validate_building(const Building& b,
                                               const ValidationOptions& opt = {});
std::vector<ValidationIssue> validate_model(const BatchModel& model,
                                            const ValidationOptions& opt = {});
// "<building>: <code> <NAME> at <where>: <message>"
std::string to_string(const ValidationIssue& issue);

}  // namespace c3d
