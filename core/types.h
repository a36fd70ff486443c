#pragma once
// Plain data passed between the pipeline stages. World coordinates (UTM, metres)
// are kept in double; the batch subtracts one LocalFrame origin so that every
// stage after ingest works in small local numbers (float-safe for PCL).
#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products are used everywhere
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <vector>

namespace c3d {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Ring2 = std::vector<Vec2>;  // closed implicitly: last vertex != first
using Ring3 = std::vector<Vec3>;  // closed implicitly

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// world = local + origin
struct LocalFrame {
  Vec3 origin = Vec3::Zero();
  Vec3 to_local(const Vec3& w) const { return w - origin; }
  Vec3 to_world(const Vec3& l) const { return l + origin; }
  Vec2 to_local(const Vec2& w) const { return w - origin.head<2>(); }
  Vec2 to_world(const Vec2& l) const { return l + origin.head<2>(); }
};

// A point cloud as read from a file: world coordinates, raw class codes.
struct PointCloud {
  std::string source;                 // file it came from
  std::vector<Vec3> points;           // world coordinates (double)
  std::vector<std::uint8_t> classes;  // one per point, or empty when the format has none
  std::string crs_wkt;                // empty when the file carries no CRS
  std::vector<std::uint8_t> returns;  // LAS return fields per point (pack_returns), or empty
};

// A point's return number (1..15) and its pulse's number of returns, packed in one byte.
inline std::uint8_t pack_returns(int number, int of) { return std::uint8_t((number & 15) << 4 | (of & 15)); }
inline int return_number(std::uint8_t packed) { return packed >> 4; }
inline int number_of_returns(std::uint8_t packed) { return packed & 15; }

// Which raw classification codes mean roof, wall and ground.
struct ClassMapping {
  std::vector<int> roof{6};
  std::vector<int> wall{64};
  std::vector<int> ground{2};
  bool is_roof(int code) const { return holds(roof, code); }
  bool is_wall(int code) const { return holds(wall, code); }
  bool is_ground(int code) const { return holds(ground, code); }

 private:
  static bool holds(const std::vector<int>& codes, int c) {
    for (int k : codes)
      if (k == c) return true;
    return false;
  }
};

struct Polygon2 {
  Ring2 outer;               // counter-clockwise
  std::vector<Ring2> holes;  // clockwise
};
using MultiPolygon2 = std::vector<Polygon2>;

// One cadastral parcel (land parcel, LADM la_spatialunit).
// One field of the parcel layer's own feature (docs/design.md, "GeoPackage"):
// the store's `parcel` layer carries it, typed as the layer had it.
struct ParcelAttribute {
  enum class Kind { Text, Integer, Real };
  std::string name;
  Kind kind = Kind::Text;
  bool is_null = true;
  std::string value;  // as OGR writes it (GetFieldAsString)
};

struct Parcel {
  int index = 0;                   // position in the layer (0-based)
  std::string id;                  // parcel id (field value or feature id)
  std::string right_type;          // e.g. "Hak Milik"
  double official_area = kNaN;     // certified area from the layer, m2
  MultiPolygon2 shape;             // world coordinates
  std::string repair_note;         // non-empty when an invalid polygon was repaired
  std::vector<ParcelAttribute> attributes;  // the layer's own fields, layer order
};

struct ParcelLayer {
  std::string source;
  std::string crs_wkt;
  std::vector<std::string> fields;
  std::vector<Parcel> parcels;
};

// Digital terrain model on a regular grid, world coordinates, holes filled.
struct Dtm {
  std::string source;
  std::string crs_wkt;
  double x0 = 0, y0 = 0;     // world coordinates of the centre of cell (0,0)
  double dx = 1, dy = -1;    // cell size (dy negative for north-up rasters)
  int nx = 0, ny = 0;
  std::vector<float> z;      // row-major, ny rows of nx; or only a window (below)
  double nodata_share = 0;   // share of cells that were NoData before filling
  // A window of a larger raster (DtmSource::window): z holds win_ny rows of
  // win_nx cells from cell (win_x, win_y); x0, y0, nx, ny stay the whole
  // raster's, so extents and lookups are computed exactly as on the whole.
  // win_nx == 0: z holds the whole grid.
  int win_x = 0, win_y = 0, win_nx = 0, win_ny = 0;
  // Height of cell (i, j) of the whole grid; NaN outside the window held.
  float cell(int i, int j) const;
  // Bilinear height at a world position; NaN outside the grid.
  double height_at(double x, double y) const;
  bool covers(double x, double y) const;
};

// ---- Building model ------------------------------------------------------

enum class ElementType { Roof, Wall, PartyWall, Ground, OuterCeiling };
// How a wall was placed: measured (its own wall points), propagated (another
// facade's overhang), default (configured overhang); a party wall stands on the
// parcel boundary, a roof step where two roof planes meet at different heights.
enum class WallEvidence { None, Measured, Propagated, Default, ParcelBoundary, RoofStep };

const char* to_string(ElementType t);
const char* to_string(WallEvidence e);

// A planar polygon in local coordinates, oriented counter-clockwise when seen
// from outside the building (normal points outward / downward for ground).
struct Face {
  Ring3 ring;
  std::vector<Ring3> holes;
};

// One building element (one roof plane, one wall, the ground floor, ...).
struct Element {
  ElementType type = ElementType::Roof;
  std::vector<Face> faces;
  double area = 0;          // true 3D area, m2 (outer ceiling: plan area, see DESIGN.md)
  double plan_area = 0;     // horizontal projection, m2
  // area and plan_area were measured on the exact curved surface, finer than
  // the faces' chords: measuring the faces again must not replace them.
  bool on_surface = false;
  double slope_deg = 0;
  double azimuth_deg = 0;   // direction the surface faces, clockwise from grid north
  double sigma_area = 0;    // 1-sigma uncertainty of area, m2
  // The part of sigma_area (signed) that moves with the same error of the
  // building's other elements of this type (one assumed overhang, one noise
  // fitted to all roof edges): totals add it linearly, the rest in quadrature.
  double sigma_shared = 0;  // m2
  int support_points = 0;   // points that supported the plane
  double rmse = 0;          // plane-fit RMSE, m
  WallEvidence evidence = WallEvidence::None;
};

struct Deviation {
  long n = 0;
  double max = 0, mean = 0, std = 0, rmse = 0;
};

// What GIS users filter on, after 3DBAG's building attributes (b3_dak_type,
// b3_h_dak_*, b3_rmse_*, point counts): computed from the building's own roof
// points by the reconstruction, stored and exported next to the element areas.
struct BuildingAttributes {
  // "horizontal", "multiple horizontal", "slanted" (3DBAG's roof types), or
  // "no points" / "could not detect" where the points do not tell.
  std::string roof_type;
  // Heights (local z) of the building's own roof points: min, 50th, 70th
  // percentile, max. NaN without roof points.
  double roof_z_min = kNaN, roof_z_50p = kNaN, roof_z_70p = kNaN, roof_z_max = kNaN;
  long roof_points = 0;          // the building's own roof points
  double point_density = kNaN;   // those points per m2 of the plan they were taken over
  // RMSE of the 3D distances of those points to the primary model's roof
  // (3DBAG's b3_rmse_lod22 for a 2.2 model), m; NaN without points.
  double roof_rmse = kNaN;
  // "good", or why the model rests on too little, "; "-joined: "no roof
  // points", "insufficient points (...)", "lod fallback (1.3)" (docs/design.md,
  // "Building attributes").
  std::string data_quality;
};

// The level of detail a building is modelled at (docs/design.md): 2.2 the
// element model (roof planes), 1.3 height layers, 1.2 one prism. Ordered
// from low to high; stores and exports write "1.2", "1.3", "2.2".
enum class Lod { Lod12, Lod13, Lod22 };
const char* to_string(Lod l);
// The level its text names; std::invalid_argument naming the text otherwise.
Lod lod_from(const std::string& text);

// The same building at a lower level of detail (1.2 prism, 1.3 layers),
// for the exports that carry several LoDs: its closed shell, outward, with
// each face's element type.
struct LodShell {
  Lod lod = Lod::Lod12;
  std::vector<Face> faces;
  std::vector<ElementType> face_types;  // one per face
  double volume = 0;                    // m3
  double roof_rmse = kNaN;              // of the roof points against this shell's roof, m
};

// The exact shape of a curved building (docs/curved.md), which its faces
// tessellate: the union of its parts, each a closed profile in the plane
// through `origin` spanned by `u` and `v`, either turned about the line
// through `origin` along `v` (a dome, cone or onion on its drum: profile in
// (distance from the axis, z)) or swept along `path` (a vault: its end
// profile in (across, z); a hall: its footprint). The profile runs from
// `start` through its steps and closes with a line back to `start`.
struct ProfileStep {
  enum class Kind { Line, Arc, Spline };
  Kind kind = Kind::Line;
  std::vector<Vec2> through;  // an arc: a point on it; a spline: the points it follows (within 5 mm)
  Vec2 to = Vec2::Zero();     // where it ends
};

// A free-form roof: a tensor-product B-spline surface z = f(x, y), its
// parameters (u, v) the plan point origin + u e1 + v e2 of an orthonormal
// frame its poles stand on. Knots flat, multiplicities repeated; poles with u
// running fastest. No poles: none.
struct SplineSurface {
  int degree_u = 3, degree_v = 3;
  int poles_u = 0, poles_v = 0;
  std::vector<Vec3> poles;
  std::vector<double> knots_u, knots_v;
  bool empty() const { return poles.empty(); }
};

struct ShapePart {
  bool revolve = false;
  Vec3 origin = Vec3::Zero(), u = Vec3::UnitX(), v = Vec3::UnitZ(), path = Vec3::Zero();
  Vec2 start = Vec2::Zero();
  std::vector<ProfileStep> steps;
  SplineSurface roof;  // a swept part cut off above it (a free-form roof over a hall); empty: none
};

struct ExactShape {
  std::vector<ShapePart> parts;  // none: the faces are the shape
};

// What the optimizer's surface snapping did to the dense mesh of a curved
// building's points (docs/curved.md, "Optimizer"); none where triangles is 0.
struct MeshRefinement {
  int triangles = 0;
  double snapped_share = kNaN;  // of its vertices, moved onto a surface of the exact shape
  // Chamfer distance of the mesh to the exact shape where the mesh stands,
  // and the mean distance of the points to the mesh, before and after, m.
  double chamfer_before_m = kNaN, chamfer_after_m = kNaN;
  double cloud_before_m = kNaN, cloud_after_m = kNaN;
};

// One level of a building's mesh ladder (core/mesh, docs/meshes.md) as the
// store, summary.json and the report keep it: its figures and its files, paths
// relative to the batch's output folder ("" where a level has none).
struct MeshLevelRecord {
  int level = 0;  // 1 (closed hull) .. 4 (dense)
  long faces = 0, vertices = 0;
  double seconds = 0;  // CPU
  // Cloud to mesh (m): the building's points to the nearest face.
  double mean_m = kNaN, std_m = kNaN, p95_m = kNaN, max_m = kNaN;
  double mesh_to_cloud_m = kNaN;  // farthest vertex or face centre from any point
  double far_share = kNaN;        // points farther than two spacings from the mesh
  bool closed = false, manifold = false;
  double volume = kNaN;     // m3, a closed level
  double roof_area = kNaN;  // m2, a closed level's faces that look up (docs/meshes.md)
  // Level 4's planar regions here (seed 002's table, core/mesh/regions.h):
  // levels 2 to 4 count them; levels 2 and 3 lose some whole, and change a
  // kept one's extent (length or width) by at most extent_change_m; thickness_m
  // is the thickest across its plane.
  long planar_regions = 0, planar_lost = 0;
  double extent_change_m = kNaN, thickness_m = kNaN;
  std::string ply, glb, picture;
  std::string ply_sha256, glb_sha256, picture_sha256;
};

// A building's mesh ladder and the element model checked against its closed
// level (docs/meshes.md, "The element model against the mesh"). Not meshed:
// method "".
struct BuildingMesh {
  std::string method;  // the dense method: front, pivot, poisson, alpha
  long points = 0;     // the building's own points meshed (roof and walls)
  double spacing_m = kNaN;  // their mean nearest-neighbour distance
  double hull_alpha_m = kNaN;  // level 1's wrap: no gap narrower than this enters it
  std::vector<MeshLevelRecord> levels;  // level 1 first; none where `problem` says why
  // The volume under the model's roof, overhangs included, down to its
  // terrain (m3), and (hull - model) / model of it and of the roof area, the
  // hull being the closed level 1.
  double model_volume = kNaN;
  double volume_diff = kNaN, roof_area_diff = kNaN;
  std::string flag;     // "" where they agree; else what to look at
  std::string problem;  // why the building has no ladder ("" when it has)
};

struct Building {
  std::string id;                 // "<parcel id>_b<k>"
  std::vector<Element> elements;
  double volume = 0;              // m3, closed solid of walls, ground, roof underside
  double eave_height = 0;         // above terrain, m
  double ridge_height = 0;        // above terrain, m
  double terrain_z = 0;           // local z of the ground floor
  int storeys = 1;
  bool solid_valid = false;       // closed, 2-manifold, outward oriented
  std::string solid_problem;      // why not valid
  // The level of detail modelled: 2.2 (roof planes, the element model), 1.3
  // (height layers, where the 2.2 model could not be made valid) or 1.2 (one
  // prism, where the layers failed too), and why it is not 2.2 ("" for a 2.2
  // model that is valid).
  Lod lod = Lod::Lod22;
  std::string lod_note;
  Deviation roof_deviation, wall_deviation;
  // The closed solid: shell faces (ground, walls, roof inside the walls).
  std::vector<Face> solid;
  BuildingAttributes attributes;
  // Valid lower LoDs of this building, lowest first (none above `lod`).
  std::vector<LodShell> lower_lods;
  ExactShape exact;  // a curved building's surfaces, exact (STEP writes them)
  MeshRefinement refinement;
  BuildingMesh mesh;  // batch --mesh only
};

// b's valid lower LoD `lod` (1.2, 1.3), or null where it has none.
const LodShell* lower_lod(const Building& b, Lod lod);

struct Timing {
  std::string stage;
  double seconds = 0;
};

// Suspect: modelled, but a figure lies outside the plausible bounds
// (cadastre/batch/plausibility.h); reported with its reason, never valued.
enum class ParcelStatus { Ok, Empty, Failed, Suspect };
const char* to_string(ParcelStatus s);
// The status its text names; std::invalid_argument naming the text otherwise.
ParcelStatus parcel_status_from(const std::string& text);

struct ParcelResult {
  int parcel_index = 0;
  std::string parcel_id;
  ParcelStatus status = ParcelStatus::Empty;
  std::string reason;
  std::vector<Building> buildings;
  std::vector<Timing> timings;
  long roof_points = 0, wall_points = 0;
};

}  // namespace c3d

namespace c3d {

// Everything a batch produced, as the store, the exports and the report see it.
struct BatchModel {
  LocalFrame frame;              // local = world - frame.origin
  std::string crs_wkt;
  int epsg = 0;                  // 0 when the CRS has no EPSG code
  std::vector<Parcel> parcels;   // world coordinates, layer order
  std::vector<ParcelResult> results;  // same order; building geometry in local coordinates
};

}  // namespace c3d
