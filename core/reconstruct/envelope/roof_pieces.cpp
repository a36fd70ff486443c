#include "core/reconstruct/envelope/roof_pieces.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <utility>

#include "core/geometry/geometry.h"
#include "core/geometry/polygon_ops.h"
#include "core/reconstruct/envelope/common.h"
#include "core/reconstruct/envelope/footprint.h"

namespace c3d::envelope {

// Parts of a region narrower than twice this are partition artefacts (spikes
// along a neighbour, slivers at the footprint), not roof a scan can support.
constexpr double kThin = 0.05;
// A separate fragment of a region smaller than this, beside a larger part of
// the same region, is an artefact too (label-grid teeth touching at corners).
constexpr double kFragment = 0.5;
// A face of the subdivision smaller than kSliver is a noding sliver; a face
// under no region smaller than kGap is a gap the partition left between two.
constexpr double kSliver = 1e-3;  // m^2
constexpr double kGap = 0.05;     // m^2
// Thin parts (narrower than 2 kThin) smaller than this are noding dust.
constexpr double kMinThinPart = 1e-4;  // m^2
// A face to merge goes to a neighbour on its own side of the walls before any
// across them, whatever the lengths shared (far more than any edge length).
constexpr double kSameSideFirst = 1e6;
// Fragments merged into their region's larger part, then looked for again:
// merging may leave new fragments, three rounds settle what the partition gives.
constexpr int kFragmentRounds = 3;
// A face merged into another region takes that region's plane, extended: on a
// steep plane a long thin strip reaches far above or below any roof (AHN3
// 09087: a 4 cm overhang strip of a flat roof, given to a 64 degree neighbour,
// dipped 16 m under the terrain). A neighbour whose plane puts a vertex of the
// face more than this beyond the heights the regions span comes after others.
constexpr double kRoofHeightMargin = 0.5;  // m
constexpr double kKeepsHeightFirst = 1e9;  // above kSameSideFirst: height before side
// After noding, an overhang frame's hole touches its outline exactly: pinch
// points are vertices closer than this (numerically one).
constexpr double kPinchTol = 1e-9;  // m

namespace {

// Faces of one planar subdivision -> for each face, the length of edge it
// shares with every other face (edges are identical, so plain keys match).
std::vector<std::map<int, double>> face_neighbours(const MultiPolygon2& faces) {
  std::map<EdgeKey, std::vector<int>> users;
  auto add = [&](const Ring2& r, int f) {
    for (size_t i = 0; i < r.size(); ++i) users[undirected(r[i], r[(i + 1) % r.size()])].push_back(f);
  };
  for (size_t f = 0; f < faces.size(); ++f) {
    add(faces[f].outer, int(f));
    for (const auto& h : faces[f].holes) add(h, int(f));
  }
  std::vector<std::map<int, double>> shared(faces.size());
  for (const auto& [e, fs] : users) {
    double len = std::hypot(e.first.first - e.second.first, e.first.second - e.second.second);
    for (int a : fs)
      for (int b : fs)
        if (a != b) shared[a][b] += len;
  }
  return shared;
}

struct FaceOwner {
  int region = -1;  // -1: not roof
  bool inside = false;
  bool merge = false;  // to be given to a neighbour
};

// Faces of one region on one side of the walls that are joined by edges.
std::vector<int> owner_components(const std::vector<FaceOwner>& owner,
                                  const std::vector<std::map<int, double>>& shared) {
  std::vector<int> comp(owner.size(), -1);
  int next = 0;
  for (size_t s = 0; s < owner.size(); ++s) {
    if (comp[s] >= 0) continue;
    std::vector<int> todo{int(s)};
    comp[s] = next;
    while (!todo.empty()) {
      int f = todo.back();
      todo.pop_back();
      for (const auto& [g, len] : shared[f])
        if (comp[g] < 0 && owner[g].region == owner[f].region && owner[g].inside == owner[f].inside)
          comp[g] = next, todo.push_back(g);
    }
    ++next;
  }
  return comp;
}

// Whether the plane of region `to` keeps every vertex of face `f` within the
// roof's heights.
using FitsRoof = std::function<bool(int f, int to)>;

// The neighbour face `f` goes to: most boundary shared, a neighbour on the
// same side of the walls first, and one whose plane keeps the face within the
// roof's heights before any other.
int merge_target(int f, const std::vector<FaceOwner>& owner,
                 const std::vector<std::map<int, double>>& shared, const FitsRoof& fits) {
  int best = -1;
  double best_score = 0;
  for (const auto& [g, len] : shared[size_t(f)]) {
    if (owner[size_t(g)].merge || owner[size_t(g)].region < 0) continue;
    const bool keeps_height = fits(f, owner[size_t(g)].region);
    const double score = len + (owner[size_t(g)].inside == owner[size_t(f)].inside ? kSameSideFirst : 0.0) +
                         (keeps_height ? kKeepsHeightFirst : 0.0);
    if (score > best_score) best = g, best_score = score;
  }
  return best;
}

// Faces marked merge take the region of the neighbour merge_target picks; a
// face never changes side (the solid's top must cover the footprint
// exactly). Repeated so chains of slivers resolve.
void merge_marked(std::vector<FaceOwner>& owner, const std::vector<std::map<int, double>>& shared,
                  const FitsRoof& fits) {
  for (bool changed = true; changed;) {
    changed = false;
    for (size_t f = 0; f < owner.size(); ++f) {
      if (!owner[f].merge) continue;
      const int best = merge_target(int(f), owner, shared, fits);
      if (best < 0) continue;
      owner[f].region = owner[best].region;  // its side of the walls stays
      owner[f].merge = false;
      changed = true;
    }
  }
  for (auto& o : owner) o.merge = false;  // nothing to join: it keeps its own region
}

// Small fragments of a region beside a larger part of it are marked merge.
bool mark_fragments(const MultiPolygon2& faces, std::vector<FaceOwner>& owner,
                    const std::vector<std::map<int, double>>& shared) {
  std::vector<int> comp = owner_components(owner, shared);
  std::map<int, double> comp_area;
  std::map<std::pair<int, bool>, double> largest;
  for (size_t f = 0; f < faces.size(); ++f) comp_area[comp[f]] += area(faces[f]);
  for (size_t f = 0; f < faces.size(); ++f) {
    double& l = largest[{owner[f].region, owner[f].inside}];
    l = std::max(l, comp_area[comp[f]]);
  }
  bool any = false;
  for (size_t f = 0; f < faces.size(); ++f) {
    double a = comp_area[comp[f]];
    if (owner[f].region >= 0 && a < kFragment && a < largest[{owner[f].region, owner[f].inside}])
      owner[f].merge = any = true;
  }
  return any;
}

// The plan with its vertices within the weld tolerance of an edge of `ring`
// put on that edge. Noding would put them into the edge where they are, and
// bend it: the pieces inside a footprint edge would then meet its wall a
// fraction of a millimetre off the wall's plane (05786 on a random quarter of
// the Cimahi points: a wall face 1 mm wide folded across its corner).
MultiPolygon2 onto_edges(MultiPolygon2 plan, const Ring2& ring) {
  auto onto = [&](Vec2& v) {
    for (size_t i = 0; i < ring.size(); ++i) {
      const Vec2 a = ring[i], d = ring[(i + 1) % ring.size()] - a;
      const double len = d.norm(), t = d.dot(v - a) / std::max(len, 1e-12);
      const Vec2 foot = a + t / std::max(len, 1e-12) * d;
      if (t > 0 && t < len && (v - foot).norm() < kWeldTol) {
        v = foot;
        return;
      }
    }
  };
  for (auto& p : plan) {
    for (auto& v : p.outer) onto(v);
    for (auto& h : p.holes)
      for (auto& v : h) onto(v);
  }
  return plan;
}

// FitsRoof over the heights of the regions' plans on their own planes,
// widened by kRoofHeightMargin.
FitsRoof fits_roof_heights(const std::vector<RoofRegion>& roof, const MultiPolygon2& faces) {
  double lo = 1e300, hi = -1e300;
  for (const auto& r : roof)
    for (const auto& p : r.plan)
      for (const Vec2& v : p.outer) {
        const double z = r.plane.z_at(v.x(), v.y());
        lo = std::min(lo, z), hi = std::max(hi, z);
      }
  return [&roof, &faces, lo, hi](int f, int to) {
    for (const Vec2& v : faces[size_t(f)].outer) {
      const double z = roof[size_t(to)].plane.z_at(v.x(), v.y());
      if (z < lo - kRoofHeightMargin || z > hi + kRoofHeightMargin) return false;
    }
    return true;
  };
}

}  // namespace

// The roof regions cut by the footprint into pieces inside the walls and
// hanging pieces, all from one planar subdivision (GEOS noding + polygonize):
// pieces that meet share their vertices exactly. Slivers, thin spikes, gaps
// and stray fragments the partition left are given to the neighbour they
// share most boundary with, never dropped (a dropped sliver is a hole in the
// shell, a spike touching a wall a pinched solid).
std::vector<Piece> roof_pieces(const std::vector<RoofRegion>& roof, const Polygon2& fp) {
  std::vector<MultiPolygon2> plans;
  MultiPolygon2 thin;
  for (const auto& r : roof) {
    plans.push_back(onto_edges(r.plan, fp.outer));
    MultiPolygon2 opened = poly::buffer(poly::buffer(plans.back(), -kThin), kThin);
    for (auto& t : poly::drop_small(poly::subtract(plans.back(), opened), kMinThinPart)) thin.push_back(t);
  }
  Polygon2 footprint = fp;
  std::vector<Ring2*> rings{&footprint.outer};
  auto add_rings = [&](MultiPolygon2& mp) {
    for (auto& p : mp) {
      rings.push_back(&p.outer);
      for (auto& h : p.holes) rings.push_back(&h);
    }
  };
  for (auto& plan : plans) add_rings(plan);
  add_rings(thin);
  node_rings(rings, kWeldTol);
  MultiPolygon2 all{footprint};
  for (const auto& plan : plans) all.insert(all.end(), plan.begin(), plan.end());
  all.insert(all.end(), thin.begin(), thin.end());
  MultiPolygon2 faces = poly::planar_faces(all);

  std::vector<FaceOwner> owner(faces.size());
  for (size_t f = 0; f < faces.size(); ++f) {
    Vec2 p = poly::interior_point(faces[f]);
    for (size_t r = 0; r < plans.size() && owner[f].region < 0; ++r)
      if (poly::covers(plans[r], p)) owner[f].region = int(r);
    owner[f].inside = poly::covers({footprint}, p);
    double a = area(faces[f]);
    owner[f].merge = a < kSliver || (owner[f].region < 0 && a < kGap) || poly::covers(thin, p);
  }
  auto shared = face_neighbours(faces);
  const FitsRoof fits = fits_roof_heights(roof, faces);
  merge_marked(owner, shared, fits);
  for (int round = 0; round < kFragmentRounds && mark_fragments(faces, owner, shared); ++round)
    merge_marked(owner, shared, fits);

  std::map<std::pair<int, bool>, MultiPolygon2> groups;
  for (size_t f = 0; f < faces.size(); ++f)
    if (owner[f].region >= 0) groups[{owner[f].region, owner[f].inside}].push_back(faces[f]);
  std::vector<Piece> pieces;
  for (auto& [key, group] : groups)
    for (auto& p : poly::unite_all({group})) pieces.push_back({key.first, key.second, p});
  return pieces;
}

std::vector<Piece> simple_pieces(std::vector<Piece> pieces, const Polygon2& fp) {
  Polygon2 fp_copy = fp;
  std::vector<Ring2*> rings{&fp_copy.outer};
  for (auto& p : pieces) {
    rings.push_back(&p.plan.outer);
    for (auto& h : p.plan.holes) rings.push_back(&h);
  }
  node_rings(rings, kWeldTol);
  std::vector<Piece> simple;
  for (const auto& p : pieces)
    for (auto& part : split_pinched(p.plan, kPinchTol))  // an overhang frame's hole touching its outline
      simple.push_back({p.region, p.inside, part});
  return simple;
}

}  // namespace c3d::envelope
