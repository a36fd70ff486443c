#include "core/reconstruct/envelope/slivers.h"

#include <algorithm>
#include <array>
#include <map>
#include <optional>
#include <set>
#include <tuple>
#include <utility>

#include "core/check/polygon_rules.h"
#include "core/check/solid_check.h"
#include "core/geometry/geometry.h"
#include "core/reconstruct/envelope/common.h"
#include "core/reconstruct/envelope/shell.h"

namespace c3d::envelope {

// A vertex closer than this to the line through its ring neighbours bulges
// too little: 0.1 mm of rounding can tilt the triangle it makes by > 5 degrees.
constexpr double kSliverHeight = 1e-3;  // m
// How far such a vertex is moved past that line, into the face: ten times
// the rounding, so the run stays bent inwards when written.
constexpr double kSliverNudge = 5e-4;  // m
// A bulging corner this close to its nearer neighbour merges into it.
constexpr double kCollapseLength = 0.01;  // m
// A vertex moved into a face stays this far from every other vertex (twice
// the weld, so rounding cannot bring it within a validator's snap).
constexpr double kClearance = 2 * kWeldTol;  // m
// A move may tilt no triangle of the faces using the vertex by more than this
// (half val3dity's 20 degrees).
constexpr double kMovedTiltDeg = 10;
// Edits can make new slivers next to old ones; a few rounds settle them.
constexpr int kSliverRounds = 3;

namespace {

using Key = std::tuple<double, double, double>;
Key key(const Vec3& v) { return {v.x(), v.y(), v.z()}; }

// One vertex of one ring that lies on the straight run between its neighbours.
struct Straight {
  size_t face = 0, ring = 0, index = 0;  // ring 0: the outer ring, k: hole k-1
  bool bulges = false;                   // the apex of a sliver triangle of the face
  Key prev, next;
  Vec3 nearer;                           // the nearer of the two neighbours
  Vec3 into;                             // where the vertex goes to turn the run away
};

Ring3& ring_of(Face& f, size_t r) { return r == 0 ? f.ring : f.holes[r - 1]; }
const Ring3& ring_of(const Face& f, size_t r) { return r == 0 ? f.ring : f.holes[r - 1]; }

// Adds the apexes of `drawn`'s sliver triangles (the vertex facing a
// triangle's longest side) as the vertices of `f` they were drawn from:
// `drawn` is `f` itself or `f` as an export rounds it.
void add_sliver_apexes(const Face& f, const Face& drawn, std::set<Key>& apexes) {
  std::map<Key, Key> source;
  for (size_t r = 0; r <= f.holes.size(); ++r)
    for (size_t i = 0; i < ring_of(f, r).size(); ++i) source[key(ring_of(drawn, r)[i])] = key(ring_of(f, r)[i]);
  for (const Triangle& t : triangulate(drawn)) {
    const std::array<Vec3, 3> v{t.a, t.b, t.c};
    size_t longest = 0;
    double len = 0;
    for (size_t k = 0; k < 3; ++k)
      if (double l = (v[(k + 1) % 3] - v[(k + 2) % 3]).norm(); l > len) len = l, longest = k;
    const double height = (t.b - t.a).cross(t.c - t.a).norm() / std::max(len, 1e-12);
    auto it = source.find(key(v[longest]));
    if (height < kSliverHeight && it != source.end()) apexes.insert(it->second);
  }
}

// The apexes of the face's sliver triangles by the triangulation validators
// make (ours, val3dity's), of the face as computed and as CityJSON writes it.
std::set<Key> sliver_apexes(const Face& f) {
  std::set<Key> apexes;
  add_sliver_apexes(f, f, apexes);
  add_sliver_apexes(f, on_export_grid(f), apexes);
  return apexes;
}

// The straight vertices of one ring; material_left: the face lies left of
// the ring's direction (seen along the face's normal n).
void find_straight(const Ring3& r, const Vec3& n, bool material_left, size_t face, size_t ring,
                   std::vector<Straight>& out) {
  const size_t m = r.size();
  if (m < 4) return;  // a triangle has no run to straighten
  for (size_t i = 0; i < m; ++i) {
    const Vec3& a = r[(i + m - 1) % m];
    const Vec3& b = r[i];
    const Vec3& c = r[(i + 1) % m];
    const Vec3 t = c - a;
    const double len2 = t.squaredNorm();
    if (len2 < 1e-18) continue;
    const double u = (b - a).dot(t) / len2;
    if (u <= 0 || u >= 1) continue;
    const Vec3 foot = a + u * t;
    if ((b - foot).norm() >= kSliverHeight) continue;
    const double side = material_left ? 1.0 : -1.0;
    const Vec3 left = n.cross(t).normalized();
    out.push_back({face, ring, i, false, key(a), key(c), (b - a).norm() < (c - b).norm() ? a : c,
                   foot + side * kSliverNudge * left});
  }
}

// The straight vertices of every face, each marked where it is the apex of
// a sliver triangle (only a face with a straight vertex is triangulated).
std::vector<Straight> straight_vertices(const std::vector<Face>& faces) {
  std::vector<Straight> out;
  for (size_t f = 0; f < faces.size(); ++f) {
    const size_t first = out.size();
    const Vec3 n = unit_normal(faces[f]);
    find_straight(faces[f].ring, n, true, f, 0, out);
    for (size_t h = 0; h < faces[f].holes.size(); ++h)
      find_straight(faces[f].holes[h], n, newell_normal(faces[f].holes[h]).dot(n) < 0, f, h + 1, out);
    if (out.size() == first) continue;
    const std::set<Key> apexes = sliver_apexes(faces[f]);
    for (size_t k = first; k < out.size(); ++k)
      out[k].bulges = apexes.count(key(ring_of(faces[f], out[k].ring)[out[k].index])) > 0;
  }
  return out;
}

// The faces using each vertex, once per use.
std::map<Key, std::vector<size_t>> vertex_uses(const std::vector<Face>& faces) {
  std::map<Key, std::vector<size_t>> uses;
  for (size_t f = 0; f < faces.size(); ++f)
    for (size_t r = 0; r <= faces[f].holes.size(); ++r)
      for (const Vec3& v : ring_of(faces[f], r)) uses[key(v)].push_back(f);
  return uses;
}

// Whether moving vertex v to `to` leaves every face using it without a
// tilted triangle, as computed and as written: a corner shared with faces
// of other planes leaves those planes when it moves.
bool move_keeps_faces_flat(const std::vector<Face>& faces, const std::vector<size_t>& users, const Key& v,
                           const Vec3& to) {
  for (size_t f : users) {
    Face moved = faces[f];
    for (size_t r = 0; r <= moved.holes.size(); ++r)
      for (Vec3& p : ring_of(moved, r))
        if (key(p) == v) p = to;
    if (tilted_triangle(moved, kMovedTiltDeg) || tilted_triangle(on_export_grid(moved), kMovedTiltDeg))
      return false;
  }
  return true;
}

// What to do with a vertex: move it, or drop it where it lies between the
// ends of its run (an element's copy of a face may use it as a corner).
struct Edit {
  std::optional<Vec3> to;  // nullopt: drop
  std::set<Key> run_ends;
};
using Edits = std::map<Key, Edit>;

// Where a bulging vertex used elsewhere as a corner goes: onto its nearer
// neighbour when that is close (the short edge between them goes, and a wall
// under it becomes a triangle), else a little into the face; a move that
// would tilt a face using the vertex is not made.
std::optional<Vec3> corner_move(const std::vector<Face>& faces, const std::vector<size_t>& users, const Key& v,
                                const Straight& s, const std::vector<Vec3>& building) {
  const Vec3 at(std::get<0>(v), std::get<1>(v), std::get<2>(v));
  if ((s.nearer - at).norm() < kCollapseLength && move_keeps_faces_flat(faces, users, v, s.nearer)) return s.nearer;
  // A validator snaps vertices closer than a millimetre into one (the weld
  // keeps them apart): the moved vertex must stay clear of the building's others.
  for (const Vec3& o : building)
    if (o != at && (o - s.into).norm() < kClearance) return std::nullopt;
  if (move_keeps_faces_flat(faces, users, v, s.into)) return s.into;
  return std::nullopt;
}

// Decides the edits of one round: a vertex whose every use is straight
// between the same two neighbours (a run shared by two faces) goes; a
// bulging one used elsewhere as a corner moves (corner_move).
Edits plan_edits(const std::vector<Face>& faces, const std::vector<Vec3>& building) {
  const std::vector<Straight> straight = straight_vertices(faces);
  std::map<Key, std::vector<const Straight*>> by_vertex;
  for (const Straight& s : straight)
    by_vertex[key(ring_of(faces[s.face], s.ring)[s.index])].push_back(&s);
  const std::map<Key, std::vector<size_t>> uses = vertex_uses(faces);
  Edits edits;
  for (const auto& [v, list] : by_vertex) {
    bool any_bulge = false;
    for (const Straight* s : list) any_bulge |= s->bulges;
    if (!any_bulge) continue;
    const std::set<Key> ends0{list[0]->prev, list[0]->next};
    bool same_run = list.size() == uses.at(v).size() && list.size() <= 2;
    for (const Straight* s : list) same_run &= std::set<Key>{s->prev, s->next} == ends0;
    if (same_run) {
      edits[v] = Edit{std::nullopt, ends0};
      continue;
    }
    for (const Straight* s : list)
      if (s->bulges) {
        if (auto to = corner_move(faces, uses.at(v), v, *s, building)) edits[v] = Edit{*to, {}};
        break;
      }
  }
  return edits;
}

// Applies edits to every ring; returns whether anything changed.
bool apply_edits(std::vector<Face>& faces, const Edits& edits) {
  if (edits.empty()) return false;
  bool changed = false;
  for (Face& f : faces)
    for (size_t r = 0; r <= f.holes.size(); ++r) {
      Ring3& ring = ring_of(f, r);
      const size_t m = ring.size();
      Ring3 out;
      for (size_t i = 0; i < m; ++i) {
        auto it = edits.find(key(ring[i]));
        const bool between_ends =
            it != edits.end() &&
            std::set<Key>{key(ring[(i + m - 1) % m]), key(ring[(i + 1) % m])} == it->second.run_ends;
        if (it == edits.end() || (!it->second.to && !between_ends)) {
          out.push_back(ring[i]);
          continue;
        }
        changed = true;
        if (it->second.to) out.push_back(*it->second.to);
      }
      // A vertex merged into its neighbour leaves it twice in a row.
      out.erase(std::unique(out.begin(), out.end()), out.end());
      while (out.size() > 1 && out.front() == out.back()) out.pop_back();
      ring = std::move(out);
    }
  faces.erase(std::remove_if(faces.begin(), faces.end(), [](const Face& f) { return f.ring.size() < 3; }),
              faces.end());
  return changed;
}

// Rounds of plan + apply on `faces`, each round's edits also applied to the
// copies in `copies` (keyed on the vertices as they were in that round).
void straighten(std::vector<Face>& faces, std::vector<Element>* copies, const std::vector<Vec3>& building) {
  for (int round = 0; round < kSliverRounds; ++round) {
    const Edits edits = plan_edits(faces, building);
    if (!apply_edits(faces, edits)) break;
    if (copies)
      for (Element& e : *copies) apply_edits(e.faces, edits);
  }
}

}  // namespace

void straighten_slivers(std::vector<Face>& solid, std::vector<Element>& elements) {
  std::vector<Vec3> building = shell_vertices(solid);
  for (const Element& e : elements) {
    const std::vector<Vec3> more = shell_vertices(e.faces);
    building.insert(building.end(), more.begin(), more.end());
  }
  straighten(solid, &elements, building);
  // An element face that differs from its shell copy (a roof's hanging part,
  // a levelled outer ceiling) may keep a sliver of its own.
  for (Element& e : elements) straighten(e.faces, nullptr, building);
  elements.erase(std::remove_if(elements.begin(), elements.end(), [](const Element& e) { return e.faces.empty(); }),
                 elements.end());
}

}  // namespace c3d::envelope
