#pragma once
// Primitive-constrained mesh optimizer (DESIGN.md "refine"): minimises
// E = alpha * fitness (weighted squared vertex-to-plane distances)
//   + beta  * junction (squared distances of junction vertices to their
//             plane-plane intersection line)
// by (1) optional curvature-driven subdivision, (2) linear junction
// optimization (split along the line, M1/M2 alignment), (3) surface
// optimization (normal clusters, one Kabsch rigid transform each, projection),
// with the per-vertex work on Vulkan and a CPU reference of every kernel.
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "core/mesh/tri_mesh.h"
#include "core/optimizer/mesh_distance.h"
#include "core/types.h"
#include "core/optimizer/vulkan_compute.h"

namespace c3d {

struct PrimitivePlane {
  Vec3 n = Vec3::UnitZ();  // unit normal
  double d = 0;            // n.p + d = 0
  double distance(const Vec3& p) const { return n.dot(p) + d; }
};

struct PrimitiveLine {
  Vec3 point = Vec3::Zero();
  Vec3 dir = Vec3::UnitX();  // unit
  int plane_a = -1, plane_b = -1;
  double distance(const Vec3& p) const { return ((p - point) - (p - point).dot(dir) * dir).norm(); }
};

// A mesh whose triangles are assigned to constraint planes (-1: free), and the
// intersection lines between pairs of those planes.
struct ConstrainedMesh {
  TriMesh mesh;
  std::vector<int> tri_plane;
  std::vector<PrimitivePlane> planes;
  std::vector<PrimitiveLine> lines;
  std::vector<double> vertex_weight;  // fitness weights, empty = all 1
};

struct OptimizerOptions {
  ComputeDevice device = ComputeDevice::Auto;
  double alpha = 1.0, beta = 1.0;
  double cluster_angle_deg = 15.0;   // epsilon: normal clustering threshold
  int cluster_samples = 256;         // vertices sampled per cluster for Kabsch
  double junction_band_m = 0.3;      // triangles this close to a line are junction triangles
  bool split_junctions = true;       // split triangles along intersection lines
  bool subdivide = false;            // surface junction optimization (curved parts)
  double curvature_threshold_deg = 5.0;
  int max_subdivision_rounds = 3;
  double view_threshold_m = 0.002;   // view-dependent: skip triangles closer than this
  int threads = 1;                   // CPU reference path; 0 = all cores
};

struct OptimizeReport {
  std::string device;              // what ran: "Vulkan: <name> (...)" or "CPU reference (...)"
  std::vector<double> energy;      // E after each stage, first = input
  double max_plane_distance = 0;   // after, over constrained vertices
  double max_line_distance = 0;    // after, over junction vertices
  int clusters = 0;
  int junction_vertices = 0;
  int triangles_split = 0;
  int triangles_subdivided = 0;
  std::vector<int> view_tasks;     // view-dependent: vertices dispatched per viewpoint
  double seconds = 0;
};

// Camera for view-dependent refinement.
struct Viewpoint {
  Vec3 eye = Vec3::Zero(), target = Vec3::UnitX(), up = Vec3::UnitZ();
  double fov_y_deg = 60, aspect = 1, near_m = 0.1, far_m = 1000;
};

// PrimitiveLine where two planes meet (point closest to the origin of both).
PrimitiveLine intersect_planes(const PrimitivePlane& a, const PrimitivePlane& b, int ia = -1, int ib = -1);
// Lines for every pair of planes whose triangles share an edge and that are not
// near-parallel (> 5 degrees apart).
std::vector<PrimitiveLine> adjacent_plane_lines(const ConstrainedMesh& m);

// Runs the whole optimizer in place.
OptimizeReport optimize_mesh(ConstrainedMesh& m, const OptimizerOptions& options);
// View-dependent incremental refinement: per viewpoint, only front-facing
// triangles inside the frustum that deviate more than view_threshold_m are refined
// (one dispatch: junction tasks first, then surface tasks).
OptimizeReport optimize_views(ConstrainedMesh& m, const std::vector<Viewpoint>& views,
                              const OptimizerOptions& options);
// E = alpha * fitness + beta * junction of the current mesh, on the CPU.
double mesh_energy(const ConstrainedMesh& m, const OptimizerOptions& options);

struct HeightFieldData;  // core/optimizer/height_field_eval.h

// A surface the optimizer snaps a mesh onto (seed 000's primitives): a
// sphere, a cylinder, a cone or a plane, perhaps bounded along a direction,
// or a free-form roof's B-spline height field, bounded by its knots' span.
struct CurvedPrimitive {
  enum class Kind { Sphere, Cylinder, Cone, Plane, HeightField };
  Kind kind = Kind::Sphere;
  Vec3 point = Vec3::Zero();  // sphere: centre; cylinder: a point on its axis; cone: apex; plane: a point on it
  Vec3 axis = Vec3::UnitZ();  // cylinder: unit axis; cone: unit axis from the apex into the cone; plane: unit normal
  double radius = 0;          // sphere, cylinder
  double angle = 0;           // cone: half-angle, rad
  // Where the surface ends, for choosing the surface a triangle is on: a
  // point's coordinate along `span` from `point` in [span_lo, span_hi]
  // (unbounded where span is zero).
  Vec3 span = Vec3::Zero();
  double span_lo = 0, span_hi = 0;
  std::shared_ptr<const HeightFieldData> heights;  // a height field's
  Vec3 project(const Vec3& p) const;  // the nearest point on the surface
  Vec3 normal(const Vec3& p) const;   // unit normal there, away from the axis or centre
  double distance(const Vec3& p) const { return (project(p) - p).norm(); }
  bool spans(const Vec3& p, double slack) const;
};

struct CurvedSnapOptions {
  ComputeDevice device = ComputeDevice::Auto;
  int threads = 1;                 // CPU reference path; 0 = all cores
  double assign_distance_m = 0.2;  // a triangle's centroid this near a surface may be on it
  double assign_angle_deg = 30;    // if its normal agrees with the surface's this well
  bool subdivide = true;           // seed 000's surface junction rule (snap_to_curved)
  double curvature_threshold_deg = 5.0;
};

struct CurvedSnapReport {
  std::string device;  // what ran, as OptimizeReport::device
  int triangles_on_surfaces = 0, vertices_snapped = 0, triangles_subdivided = 0;
  double mean_distance_before = 0, mean_distance_after = 0;  // snapped vertices to their surface, m
};

// Surface snapping onto primitives: a triangle whose centroid lies within
// assign_distance of a surface and its span, its normal agreeing with the
// surface's, is on the nearest such; its vertices are projected onto it along
// the surface normal (a vertex on two: onto the nearer), in float about the
// mesh's centre, on Vulkan (shaders/opt_snap_curved.comp) or the CPU
// reference. Then triangles the surfaces under them turn across by more than
// the curvature threshold are split at their edge midpoints, snapped in turn
// (once; three times over ten times the threshold).
CurvedSnapReport snap_to_curved(TriMesh& mesh, const std::vector<CurvedPrimitive>& surfaces,
                                const CurvedSnapOptions& options);

// For the batch: triangulates the element faces (which lie on fitted planes),
// refits each face's plane to the points when given, runs the optimizer
// (planarity, junction consistency) and writes the refined vertices back into
// the element faces and the solid.
OptimizeReport optimize_building(Building& building, const std::vector<Vec3>& points,
                                 const OptimizerOptions& options);

}  // namespace c3d
