#pragma once
// Hand-built BatchModels for the export and validation tests (no other module needed):
// a gable house with a hanging roof, two attached houses with a party wall on
// neighbouring parcels, and a building with two roof levels. Local coordinates;
// the frame origin is a UTM 48S position near Cimahi.
#include <cmath>
#include <string>
#include <vector>

#include "core/geometry/geometry.h"
#include "core/types.h"

namespace c3d::fixture {

inline Face face(std::initializer_list<Vec3> ring, std::vector<Ring3> holes = {}) {
  Face f;
  f.ring = ring;
  f.holes = std::move(holes);
  return f;
}

inline Vec3 shift(const Vec3& p, const Vec3& d) { return p + d; }

inline Element element(ElementType t, std::vector<Face> faces, double sigma = 0.1) {
  Element e;
  e.type = t;
  e.faces = std::move(faces);
  for (const auto& f : e.faces) {
    e.area += area(f);
    e.plan_area += plan_area(f);
  }
  if (t == ElementType::OuterCeiling) e.area = e.plan_area;
  Vec3 n = unit_normal(e.faces.front());
  e.slope_deg = std::acos(std::min(1.0, std::abs(n.z()))) * 180 / M_PI;
  e.azimuth_deg = std::fmod(std::atan2(n.x(), n.y()) * 180 / M_PI + 360, 360);
  e.sigma_area = sigma;
  e.support_points = 120;
  e.rmse = 0.03;
  e.evidence = (t == ElementType::Wall || t == ElementType::PartyWall) ? WallEvidence::Measured
                                                                       : WallEvidence::None;
  return e;
}

// Moves every face of a building by d (to place copies side by side).
inline void translate(Building& b, const Vec3& d) {
  auto move = [&](Face& f) {
    for (auto& p : f.ring) p += d;
    for (auto& h : f.holes) for (auto& p : h) p += d;
  };
  for (auto& e : b.elements) for (auto& f : e.faces) move(f);
  for (auto& f : b.solid) move(f);
  b.terrain_z += d.z();
}

// 10 x 8 m, eaves 3 m, ridge 6 m along x, 0.5 m overhang all round.
inline Building gable_house(const std::string& id) {
  Building b;
  b.id = id;
  using E = ElementType;
  const double o = 0.5, ze = 3.0 - o * 3.0 / 4.0;  // roof edge height at the overhang
  Face ground = face({{0, 0, 0}, {0, 8, 0}, {10, 8, 0}, {10, 0, 0}});
  Face south = face({{0, 0, 0}, {10, 0, 0}, {10, 0, 3}, {0, 0, 3}});
  Face north = face({{10, 8, 0}, {0, 8, 0}, {0, 8, 3}, {10, 8, 3}});
  Face east = face({{10, 0, 0}, {10, 8, 0}, {10, 8, 3}, {10, 4, 6}, {10, 0, 3}});
  Face west = face({{0, 8, 0}, {0, 0, 0}, {0, 0, 3}, {0, 4, 6}, {0, 8, 3}});
  Face roof_s = face({{-o, -o, ze}, {10 + o, -o, ze}, {10 + o, 4, 6}, {-o, 4, 6}});
  Face roof_n = face({{10 + o, 8 + o, ze}, {-o, 8 + o, ze}, {-o, 4, 6}, {10 + o, 4, 6}});
  // Underside of the overhang: a horizontal frame (normal down) around the footprint.
  Face ceiling = face({{-o, -o, ze}, {-o, 8 + o, ze}, {10 + o, 8 + o, ze}, {10 + o, -o, ze}},
                      {{{0, 0, ze}, {10, 0, ze}, {10, 8, ze}, {0, 8, ze}}});
  b.elements = {element(E::Roof, {roof_s}), element(E::Roof, {roof_n}),
                element(E::Wall, {south}),  element(E::Wall, {north}),
                element(E::Wall, {east}),   element(E::Wall, {west}),
                element(E::Ground, {ground}), element(E::OuterCeiling, {ceiling})};
  b.solid = {ground, south, north, east, west,
             face({{0, 0, 3}, {10, 0, 3}, {10, 4, 6}, {0, 4, 6}}),
             face({{10, 8, 3}, {0, 8, 3}, {0, 4, 6}, {10, 4, 6}})};
  b.volume = 360;
  b.eave_height = 3;
  b.ridge_height = 6;
  b.storeys = 1;
  b.solid_valid = true;
  return b;
}

// House A (0..8 x 0..10, flat roof 6 m) and house B (8..16, flat roof 4 m) share
// the wall x = 8 up to 4 m; above it A has an exterior wall.
inline Building attached_a(const std::string& id) {
  using E = ElementType;
  Building b;
  b.id = id;
  Face ground = face({{0, 0, 0}, {0, 10, 0}, {8, 10, 0}, {8, 0, 0}});
  Face west = face({{0, 10, 0}, {0, 0, 0}, {0, 0, 6}, {0, 10, 6}});
  Face south = face({{0, 0, 0}, {8, 0, 0}, {8, 0, 4}, {8, 0, 6}, {0, 0, 6}});
  Face north = face({{8, 10, 0}, {0, 10, 0}, {0, 10, 6}, {8, 10, 6}, {8, 10, 4}});
  Face party = face({{8, 0, 0}, {8, 10, 0}, {8, 10, 4}, {8, 0, 4}});
  Face upper = face({{8, 0, 4}, {8, 10, 4}, {8, 10, 6}, {8, 0, 6}});
  Face roof = face({{0, 0, 6}, {8, 0, 6}, {8, 10, 6}, {0, 10, 6}});
  b.elements = {element(E::Roof, {roof}),      element(E::Wall, {west}),
                element(E::Wall, {south}),     element(E::Wall, {north}),
                element(E::Wall, {upper}),     element(E::PartyWall, {party}),
                element(E::Ground, {ground})};
  b.solid = {ground, west, south, north, party, upper, roof};
  b.volume = 480;
  b.eave_height = b.ridge_height = 6;
  b.storeys = 2;
  b.solid_valid = true;
  return b;
}

inline Building attached_b(const std::string& id) {
  using E = ElementType;
  Building b;
  b.id = id;
  Face ground = face({{8, 0, 0}, {8, 10, 0}, {16, 10, 0}, {16, 0, 0}});
  Face party = face({{8, 10, 0}, {8, 0, 0}, {8, 0, 4}, {8, 10, 4}});
  Face east = face({{16, 0, 0}, {16, 10, 0}, {16, 10, 4}, {16, 0, 4}});
  Face south = face({{8, 0, 0}, {16, 0, 0}, {16, 0, 4}, {8, 0, 4}});
  Face north = face({{16, 10, 0}, {8, 10, 0}, {8, 10, 4}, {16, 10, 4}});
  Face roof = face({{8, 0, 4}, {16, 0, 4}, {16, 10, 4}, {8, 10, 4}});
  b.elements = {element(E::Roof, {roof}),   element(E::Wall, {east}),
                element(E::Wall, {south}),  element(E::Wall, {north}),
                element(E::PartyWall, {party}), element(E::Ground, {ground})};
  b.solid = {ground, party, east, south, north, roof};
  b.volume = 320;
  b.eave_height = b.ridge_height = 4;
  b.storeys = 1;
  b.solid_valid = true;
  return b;
}

// Main block 0..10 x 0..6 (flat roof 7 m) and a wing 10..16 (flat roof 3.5 m);
// the long walls are single L-shaped (non-convex) polygons.
inline Building two_levels(const std::string& id) {
  using E = ElementType;
  Building b;
  b.id = id;
  Face ground = face({{0, 0, 0}, {0, 6, 0}, {16, 6, 0}, {16, 0, 0}});
  Face south = face({{0, 0, 0}, {16, 0, 0}, {16, 0, 3.5}, {10, 0, 3.5}, {10, 0, 7}, {0, 0, 7}});
  Face north = face({{16, 6, 0}, {0, 6, 0}, {0, 6, 7}, {10, 6, 7}, {10, 6, 3.5}, {16, 6, 3.5}});
  Face west = face({{0, 6, 0}, {0, 0, 0}, {0, 0, 7}, {0, 6, 7}});
  Face east = face({{16, 0, 0}, {16, 6, 0}, {16, 6, 3.5}, {16, 0, 3.5}});
  Face step = face({{10, 0, 3.5}, {10, 6, 3.5}, {10, 6, 7}, {10, 0, 7}});
  Face high = face({{0, 0, 7}, {10, 0, 7}, {10, 6, 7}, {0, 6, 7}});
  Face low = face({{10, 0, 3.5}, {16, 0, 3.5}, {16, 6, 3.5}, {10, 6, 3.5}});
  b.elements = {element(E::Roof, {high}),  element(E::Roof, {low}),  element(E::Wall, {south}),
                element(E::Wall, {north}), element(E::Wall, {west}), element(E::Wall, {east}),
                element(E::Wall, {step}),  element(E::Ground, {ground})};
  b.solid = {ground, south, north, west, east, step, high, low};
  b.volume = 546;
  b.eave_height = 3.5;
  b.ridge_height = 7;
  b.storeys = 2;
  b.solid_valid = true;
  return b;
}

inline Parcel parcel(int index, const std::string& id, const Vec3& origin, double x0, double x1,
                     double y0, double y1) {
  Parcel p;
  p.index = index;
  p.id = id;
  p.right_type = index % 2 ? "Hak Guna Bangunan" : "Hak Milik";
  Polygon2 poly;
  for (auto [x, y] : {std::pair{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}})
    poly.outer.push_back(Vec2(x, y) + origin.head<2>());
  p.shape = {poly};
  p.official_area = (x1 - x0) * (y1 - y0);
  return p;
}

inline ParcelResult result(const Parcel& p, std::vector<Building> buildings) {
  ParcelResult r;
  r.parcel_index = p.index;
  r.parcel_id = p.id;
  r.status = buildings.empty() ? ParcelStatus::Empty : ParcelStatus::Ok;
  r.buildings = std::move(buildings);
  return r;
}

// The three cases on four parcels (the attached houses stand on neighbouring parcels).
inline BatchModel sample_batch() {
  BatchModel m;
  m.frame.origin = Vec3(789012.0, 9237654.0, 700.0);
  m.epsg = 32748;
  m.crs_wkt = "EPSG:32748";
  const Vec3 o = m.frame.origin;
  Building gable = gable_house("P-001_b1");
  Building a = attached_a("P-002_b1"), bb = attached_b("P-003_b1");
  Building two = two_levels("P-004_b1");
  translate(a, {30, 0, 0.5});
  translate(bb, {30, 0, 0.5});
  translate(two, {60, 0, 1.0});
  m.parcels = {parcel(0, "P-001", o, -3, 13, -3, 11), parcel(1, "P-002", o, 27, 38, -3, 13),
               parcel(2, "P-003", o, 38, 49, -3, 13), parcel(3, "P-004", o, 57, 79, -3, 9)};
  m.results = {result(m.parcels[0], {gable}), result(m.parcels[1], {a}),
               result(m.parcels[2], {bb}), result(m.parcels[3], {two})};
  return m;
}

// Houses [first, first + count) of a grid of gable houses 40 wide, one per
// parcel (benchmark input; a page of them at a time).
inline BatchModel grid_houses(int first, int count) {
  BatchModel m;
  m.frame.origin = Vec3(789012.0, 9237654.0, 700.0);
  m.epsg = 32748;
  const int cols = 40;
  for (int i = first; i < first + count; ++i) {
    double x = (i % cols) * 20.0, y = (i / cols) * 20.0;
    Parcel p = parcel(i, "G-" + std::to_string(i), m.frame.origin, x - 3, x + 15, y - 3, y + 15);
    Building b = gable_house(p.id + "_b1");
    translate(b, {x, y, 0});
    m.parcels.push_back(p);
    m.results.push_back(result(p, {b}));
  }
  return m;
}

// n gable houses on the grid.
inline BatchModel grid_batch(int n) { return grid_houses(0, n); }

}  // namespace c3d::fixture

// ---- helpers for the independent checks (external tools) -------------------
#include <array>
#include <cstdio>
#include <filesystem>
#include <sys/wait.h>

namespace c3d::fixture {

// Runs a shell command; returns its exit code, stdout+stderr in *out.
inline int sh(const std::string& cmd, std::string* out = nullptr) {
  FILE* pipe = popen((cmd + " 2>&1").c_str(), "r");
  if (!pipe) return -1;
  std::array<char, 4096> buf;
  std::string s;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0) s.append(buf.data(), n);
  int status = pclose(pipe);
  if (out) *out = s;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

inline bool have_program(const std::string& name) {
  return sh("command -v " + name + " >/dev/null") == 0;
}

// tests/js with its npm packages installed (scripts/setup.sh), or "" (the tests
// that need them then skip): node on the PATH and every package the checks use.
inline std::string js_dir() {
  namespace fs = std::filesystem;
  fs::path p = fs::path(C3D_SOURCE_DIR) / "tests" / "js";
  fs::path m = p / "node_modules";
  bool installed = fs::exists(m / ".bin" / "ajv") && fs::exists(m / "ajv-formats" / "package.json") &&
                   fs::exists(m / "web-ifc" / "package.json");
  return installed && have_program("node") ? p.string() : "";
}

inline std::string read_text(const std::string& path) {
  FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return {};
  std::string s;
  std::array<char, 65536> buf;
  size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), f)) > 0) s.append(buf.data(), n);
  std::fclose(f);
  return s;
}

inline void write_text(const std::string& path, const std::string& text) {
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return;
  std::fwrite(text.data(), 1, text.size(), f);
  std::fclose(f);
}

}  // namespace c3d::fixture
