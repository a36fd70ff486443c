#pragma once
// The sample town's internals (core/synthetic/ only): the random source, the
// building groups the truth is built from, and the steps the town is made of.
//   sample_geometry.cpp  convex polygons in the building frame, shell checks
//   sample_buildings.cpp building groups -> exact truth buildings
//   sample_curved.cpp    curved truth buildings (vaults, domes, cones)
//   sample_town.cpp      the town: parcels, terrain, placing the buildings
//   sample_scan.cpp      the simulated UAV / handheld point cloud
//   sample_trees.cpp     trees and garden sheds on open land (options, for the classifier)
//   sample_files.cpp     parcels, DTM, cloud and truth.json on disk
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "core/synthetic/sample_town.h"

namespace c3d::sample_detail {

constexpr double kPi = 3.14159265358979323846;
constexpr double kAreaEps = 1e-10;  // m2: polygon pieces smaller than this are dropped

// ---- Randomness: raw mt19937_64 output only, identical on every platform ----

class Rng {
 public:
  explicit Rng(std::uint64_t seed) : e_(seed) {}
  double uniform() { return double(e_() >> 11) * (1.0 / 9007199254740992.0); }  // [0,1)
  double uniform(double a, double b) { return a + (b - a) * uniform(); }
  bool chance(double p) { return uniform() < p; }
  double normal() {  // Marsaglia polar method
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double x, y, s;
    do {
      x = 2 * uniform() - 1;
      y = 2 * uniform() - 1;
      s = x * x + y * y;
    } while (s >= 1 || s == 0);
    double f = std::sqrt(-2 * std::log(s) / s);
    spare_ = y * f;
    has_spare_ = true;
    return x * f;
  }
  // Randomised rounding keeps the expected count exact for small faces.
  long count(double expected) {
    double f = std::floor(expected);
    return long(f) + (chance(expected - f) ? 1 : 0);
  }

 private:
  std::mt19937_64 e_;
  double spare_ = 0;
  bool has_spare_ = false;
};

// ---- Convex polygons and planes in the building frame (sample_geometry.cpp) ----

struct Plane {  // z = a u + b v + c
  double a = 0, b = 0, c = 0;
  double z(const Vec2& p) const { return a * p.x() + b * p.y() + c; }
};

// Edge half-planes (inside >= 0) of a counter-clockwise convex polygon.
struct Line {
  double a, b, c;
};
std::vector<Line> edges_of(const Ring2& r);
double poly_area(const Ring2& r);
// Keeps the part of poly where hi - lo >= 0 (ties kept when keep_tie).
Ring2 clip_by_plane_diff(const Ring2& poly, const Plane& hi, const Plane& lo, bool keep_tie);
// Convex p intersected with convex counter-clockwise r.
Ring2 intersect(Ring2 p, const Ring2& r);
// p minus convex r as convex pieces.
std::vector<Ring2> subtract(Ring2 p, const Ring2& r);
Ring3 lift(const Ring2& r, const Plane& pl);
// The ring without repeated consecutive vertices (closing repeat included).
Ring3 dedupe(const Ring3& r);

// ---- Building groups: blocks with footprint, roof region and planes ----

struct Rect {
  double u0, u1, v0, v1;
  Ring2 ring() const { return {{u0, v0}, {u1, v0}, {u1, v1}, {u0, v1}}; }
  bool contains(const Vec2& p) const {
    return p.x() >= u0 && p.x() <= u1 && p.y() >= v0 && p.y() <= v1;
  }
};

struct Block {
  Rect footprint;
  Rect region;               // roof region: footprint plus overhang
  std::vector<Plane> planes; // roof = min of the planes over the region
  int owner = 0;             // building index within the group
};

struct Group {
  std::vector<Block> blocks;
  int owners = 1;
  std::string roof_type;
};

// The blocks of one parameter set (sample_buildings.cpp).
Group build_group(const BuildingParams& p);
// Elements, solid, footprint and heights of every building of a group, in the
// group frame with the ground floor at z = 0.
std::vector<TruthBuilding> assemble(const Group& g);
// Area, plan area, slope, azimuth from the faces (same rules as core/measure.h).
void measure(Element& e);

// ---- Curved buildings (sample_curved.cpp) ----

bool is_curved(SampleLayout l);
// One curved building in its frame: footprint in [0,length] x [0,width] (round
// ones: a circle of diameter min(length, width)), ground floor at z = 0, no
// overhang; exact areas and volume (TruthBuilding::exact_areas).
TruthBuilding make_curved_building(const BuildingParams& p);

// ---- The town (sample_town.cpp) and its point cloud (sample_scan.cpp) ----

struct Placement {
  Vec2 centre;       // local xy of the group frame origin
  double angle = 0;  // group frame -> local rotation
  Vec2 to_local(const Vec2& q) const {
    double c = std::cos(angle), s = std::sin(angle);
    return centre + Vec2(c * q.x() - s * q.y(), s * q.x() + c * q.y());
  }
  Vec2 to_group(const Vec2& p) const {
    double c = std::cos(angle), s = std::sin(angle);
    Vec2 d = p - centre;
    return {c * d.x() + s * d.y(), -s * d.x() + c * d.y()};
  }
};

struct TownParcel {
  Rect rect;        // town frame (s along the street, t across)
  bool north_row;   // front on the north street
};

// Roof, wall and open-ground points of every parcel into town.cloud.
void sample_points(SampleTown& town, const SampleOptions& opt, Rng& rng,
                   const std::vector<TownParcel>& tp, double town_angle);
// opt.trees_per_parcel trees per parcel on its open land (sample_trees.cpp).
void sample_trees(SampleTown& town, const SampleOptions& opt, const std::vector<TownParcel>& tp,
                  double town_angle);
// opt.sheds_per_parcel garden sheds per parcel on its open land (sample_trees.cpp).
void sample_sheds(SampleTown& town, const SampleOptions& opt, const std::vector<TownParcel>& tp,
                  double town_angle);

}  // namespace c3d::sample_detail
