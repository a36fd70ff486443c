#pragma once
// val3dity's ring and polygon rules (ISO 19107 as val3dity applies them), in
// one place for `cadastre3d validate` and for the reconstruction, which checks
// its own faces against them before it calls a building valid.
#include <array>
#include <map>
#include <string>
#include <vector>

#include "core/types.h"

namespace c3d {

// val3dity error codes.
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

// CityJSON writes vertices as integers on this grid (local frame); rounding to
// whole mm would tilt the thinnest faces. A face must pass the rules there too.
constexpr double kExportGridM = 0.0001;

// The face with its vertices rounded to kExportGridM, as CityJSON carries it.
Face on_export_grid(Face f);

struct PolygonRules {
  double snap_tol = 0.001;       // vertices closer than this are one vertex (m)
  double planarity_tol = 0.01;   // max distance to the fitted plane (m)
  double normals_tol_deg = 20;   // max triangle-normal deviation (204)
};

// Vertices snapped to a grid of snap_tol: equal ids mean "same vertex".
class VertexSnap {
 public:
  explicit VertexSnap(double tol) : tol_(tol) {}
  int id(const Vec3& p);
  double tol() const { return tol_; }
  std::vector<Vec3> points;  // by id

 private:
  double tol_;
  std::map<std::array<long long, 3>, int> map_;
};

struct PolygonIssue {
  int code = 0;
  std::string where;    // "" for the outer ring, " hole k" for a hole
  std::string message;
};

// Checks one face: each ring (101, 102, 104), then planarity (203, then 204).
// Appends each ring's vertex ids (consecutive repeats dropped) to `rings` and
// any issue to `issues`; false when the face is unusable.
bool check_polygon(const Face& f, const PolygonRules& rules, VertexSnap& snap,
                   std::vector<std::vector<int>>& rings, std::vector<PolygonIssue>& issues);

// The faces as val3dity reads one surface: each vertex merged into the first
// one it read within tol, across all the faces. A face that passes alone can
// tilt or fold once a neighbour's vertex 0.9 mm away replaces its own.
std::vector<Face> snapped_together(std::vector<Face> faces, double tol);

}  // namespace c3d
