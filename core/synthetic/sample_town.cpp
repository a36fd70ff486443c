#include "core/synthetic/sample_town.h"

#include <Eigen/Geometry>
#include <gdal_priv.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <stdexcept>

#include "core/gdal_dataset.h"
#include "core/geometry/geometry.h"
#include "core/io/point_io.h"

namespace c3d {

const char* to_string(SampleLayout l) {
  switch (l) {
    case SampleLayout::Gable: return "gable";
    case SampleLayout::Hip: return "hip";
    case SampleLayout::CrossGable: return "cross_gable";
    case SampleLayout::Shed: return "shed";
    case SampleLayout::Flat: return "flat";
    case SampleLayout::TwoLevel: return "two_level";
    case SampleLayout::RowHouse: return "row_gable";
    case SampleLayout::Empty: return "empty";
  }
  return "?";
}

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kAreaEps = 1e-10;

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

// ---- Convex polygons and planes in the building frame ----

struct Plane {  // z = a u + b v + c
  double a = 0, b = 0, c = 0;
  double z(const Vec2& p) const { return a * p.x() + b * p.y() + c; }
};

double poly_area(const Ring2& r) { return r.size() < 3 ? 0.0 : std::abs(signed_area(r)); }

// Keeps the part of a convex polygon where a u + b v + c >= 0. A degenerate
// half-plane (a = b = 0) keeps all when c > 0, or c == 0 and keep_tie.
Ring2 clip(const Ring2& poly, double a, double b, double c, bool keep_tie = true) {
  double n = std::hypot(a, b);
  if (n < 1e-12) return (c > 1e-12 || (std::abs(c) <= 1e-12 && keep_tie)) ? poly : Ring2{};
  a /= n, b /= n, c /= n;
  Ring2 out;
  for (size_t i = 0, k = poly.size(); i < k; ++i) {
    const Vec2& p = poly[i];
    const Vec2& q = poly[(i + 1) % k];
    double fp = a * p.x() + b * p.y() + c, fq = a * q.x() + b * q.y() + c;
    if (fp >= 0) out.push_back(p);
    if ((fp > 0 && fq < 0) || (fp < 0 && fq > 0)) out.push_back(p + (q - p) * (fp / (fp - fq)));
  }
  Ring2 clean;
  for (const auto& p : out)
    if (clean.empty() || (p - clean.back()).norm() > 1e-12) clean.push_back(p);
  while (clean.size() > 1 && (clean.front() - clean.back()).norm() <= 1e-12) clean.pop_back();
  return clean.size() < 3 ? Ring2{} : clean;
}

Ring2 clip_by_plane_diff(const Ring2& poly, const Plane& hi, const Plane& lo, bool keep_tie) {
  // keep where hi - lo >= 0
  return clip(poly, hi.a - lo.a, hi.b - lo.b, hi.c - lo.c, keep_tie);
}

// Edge half-planes (inside >= 0) of a counter-clockwise convex polygon.
struct Line {
  double a, b, c;
};
std::vector<Line> edges_of(const Ring2& r) {
  std::vector<Line> out;
  for (size_t i = 0, k = r.size(); i < k; ++i) {
    Vec2 d = r[(i + 1) % k] - r[i];
    double a = -d.y(), b = d.x();
    out.push_back({a, b, -(a * r[i].x() + b * r[i].y())});
  }
  return out;
}

Ring2 intersect(Ring2 p, const Ring2& r) {
  for (const auto& l : edges_of(r)) {
    if (p.empty()) break;
    p = clip(p, l.a, l.b, l.c);
  }
  return p;
}

// p minus convex r as convex pieces.
std::vector<Ring2> subtract(Ring2 p, const Ring2& r) {
  std::vector<Ring2> out;
  for (const auto& l : edges_of(r)) {
    if (p.empty()) break;
    Ring2 o = clip(p, -l.a, -l.b, -l.c);
    if (poly_area(o) > kAreaEps) out.push_back(o);
    p = clip(p, l.a, l.b, l.c);
  }
  return out;
}

Ring3 lift(const Ring2& r, const Plane& pl) {
  Ring3 out;
  for (const auto& p : r) out.emplace_back(p.x(), p.y(), pl.z(p));
  return out;
}

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

struct Piece {
  Ring2 poly;  // convex, counter-clockwise
  int block, plane;
  const Plane* pl;
};

std::vector<Piece> roof_pieces(const Group& g) {
  std::vector<Piece> pieces;
  for (int b = 0; b < int(g.blocks.size()); ++b) {
    const Block& B = g.blocks[b];
    for (int i = 0; i < int(B.planes.size()); ++i) {
      Ring2 poly = B.region.ring();
      for (int j = 0; j < int(B.planes.size()) && !poly.empty(); ++j)
        if (j != i) poly = clip_by_plane_diff(poly, B.planes[j], B.planes[i], j > i);
      if (poly_area(poly) > kAreaEps) pieces.push_back({poly, b, i, &B.planes[i]});
    }
  }
  // Where roof regions overlap the higher roof wins (ties: the earlier block).
  for (int c = 0; c < int(g.blocks.size()); ++c) {
    const Block& C = g.blocks[c];
    const Ring2 rc = C.region.ring();
    std::vector<Piece> next;
    for (const Piece& pc : pieces) {
      if (pc.block == c || poly_area(intersect(pc.poly, rc)) <= kAreaEps) {
        next.push_back(pc);
        continue;
      }
      for (auto& o : subtract(pc.poly, rc)) next.push_back({o, pc.block, pc.plane, pc.pl});
      for (int j = 0; j < int(C.planes.size()); ++j) {
        Ring2 q = intersect(pc.poly, rc);
        for (int k = 0; k < int(C.planes.size()) && !q.empty(); ++k)
          if (k != j) q = clip_by_plane_diff(q, C.planes[k], C.planes[j], k > j);
        if (!q.empty()) q = clip_by_plane_diff(q, *pc.pl, C.planes[j], pc.block < c);
        if (poly_area(q) > kAreaEps) next.push_back({q, pc.block, pc.plane, pc.pl});
      }
    }
    pieces = std::move(next);
  }
  return pieces;
}

// Roof height along p0->p1 as seen from the side `side` (unit): (t, z) points.
std::vector<Vec2> roof_profile(const std::vector<Piece>& pieces, const Vec2& p0, const Vec2& p1,
                               const Vec2& side) {
  struct Span {
    double lo, hi;
    const Plane* pl;
  };
  std::vector<Span> spans;
  const Vec2 d = p1 - p0;
  for (const Piece& pc : pieces) {
    double lo = 0, hi = 1;
    auto lines = edges_of(pc.poly);
    for (auto l : lines) {
      double n = std::hypot(l.a, l.b);
      l = {l.a / n, l.b / n, l.c / n};
      double f0 = l.a * p0.x() + l.b * p0.y() + l.c, f1 = l.a * p1.x() + l.b * p1.y() + l.c;
      if (std::abs(f0) < 1e-9 && std::abs(f1) < 1e-9) continue;  // segment on this edge
      double s = f1 - f0;
      if (std::abs(s) < 1e-15) {
        if (f0 < 0) hi = -1;
      } else if (s > 0) {
        lo = std::max(lo, -f0 / s);
      } else {
        hi = std::min(hi, -f0 / s);
      }
    }
    if (hi - lo < 1e-9) continue;
    Vec2 m = p0 + d * (0.5 * (lo + hi)) + side * 1e-6;
    bool inside = true;
    for (auto l : lines)
      if ((l.a * m.x() + l.b * m.y() + l.c) / std::hypot(l.a, l.b) < -1e-12) inside = false;
    if (inside) spans.push_back({lo, hi, pc.pl});
  }
  std::sort(spans.begin(), spans.end(), [](const Span& a, const Span& b) { return a.lo < b.lo; });
  if (spans.empty() || spans.front().lo > 1e-7 || spans.back().hi < 1 - 1e-7)
    throw std::logic_error("sample town: roof does not cover a wall line");
  std::vector<Vec2> out;
  for (size_t i = 0; i < spans.size(); ++i) {
    if (i > 0 && spans[i].lo > spans[i - 1].hi + 1e-7)
      throw std::logic_error("sample town: gap in the roof over a wall line");
    for (double t : {spans[i].lo, spans[i].hi}) {
      t = std::clamp(t, 0.0, 1.0);
      Vec2 q(t, spans[i].pl->z(p0 + d * t));
      if (out.empty() || std::abs(q.x() - out.back().x()) > 1e-9 ||
          std::abs(q.y() - out.back().y()) > 1e-9)
        out.push_back(q);
    }
  }
  out.front().x() = 0;
  out.back().x() = 1;
  return out;
}

Ring3 dedupe(const Ring3& r) {
  Ring3 out;
  for (const auto& p : r)
    if (out.empty() || (p - out.back()).norm() > 1e-9) out.push_back(p);
  while (out.size() > 1 && (out.front() - out.back()).norm() <= 1e-9) out.pop_back();
  return out;
}

// Vertical face between a lower and an upper profile along p0->p1.
Face vertical_face(const Vec2& p0, const Vec2& p1, const std::vector<Vec2>& bottom,
                   const std::vector<Vec2>& top) {
  Ring3 r;
  auto at = [&](const Vec2& tz) {
    Vec2 q = p0 + (p1 - p0) * tz.x();
    return Vec3(q.x(), q.y(), tz.y());
  };
  for (const auto& tz : bottom) r.push_back(at(tz));
  for (auto it = top.rbegin(); it != top.rend(); ++it) r.push_back(at(*it));
  return {dedupe(r), {}};
}

// Linear interpolation in a (t, z) profile.
double z_at(const std::vector<Vec2>& prof, double t) {
  for (size_t i = 0; i + 1 < prof.size(); ++i)
    if (t <= prof[i + 1].x() + 1e-12) {
      double w = prof[i + 1].x() - prof[i].x();
      return w < 1e-12 ? prof[i].y() : prof[i].y() + (prof[i + 1].y() - prof[i].y()) * (t - prof[i].x()) / w;
    }
  return prof.back().y();
}

// Smallest and largest top - bottom over the breakpoints of both profiles.
std::pair<double, double> height_gap(const std::vector<Vec2>& top, const std::vector<Vec2>& bottom) {
  double lo = 1e300, hi = -1e300;
  for (const auto* prof : {&top, &bottom})
    for (const auto& tz : *prof) {
      double diff = z_at(top, tz.x()) - z_at(bottom, tz.x());
      lo = std::min(lo, diff), hi = std::max(hi, diff);
    }
  return {lo, hi};
}

struct EdgePart {
  Vec2 p0, p1;
  int neighbour;  // block on the other side, -1 = outside
};

// The edges of block b's footprint (counter-clockwise), split where another
// block's footprint lies on the other side.
std::vector<EdgePart> edge_parts(const Group& g, int b) {
  std::vector<EdgePart> out;
  Ring2 r = g.blocks[b].footprint.ring();
  for (size_t e = 0; e < 4; ++e) {
    Vec2 a = r[e], z = r[(e + 1) % 4], d = z - a;
    double len2 = d.squaredNorm();
    std::vector<std::pair<double, double>> iv;
    std::vector<int> who;
    for (int c = 0; c < int(g.blocks.size()); ++c) {
      if (c == b) continue;
      Ring2 rc = g.blocks[c].footprint.ring();
      for (size_t f = 0; f < 4; ++f) {
        Vec2 ca = rc[f], cz = rc[(f + 1) % 4];
        Vec2 cd = cz - ca;
        auto cross = [](const Vec2& x, const Vec2& y) { return x.x() * y.y() - x.y() * y.x(); };
        if (std::abs(cross(d, ca - a)) > 1e-9 * std::sqrt(len2) || cd.dot(d) >= 0 ||
            std::abs(cross(d, cd)) > 1e-9)
          continue;
        double t0 = (ca - a).dot(d) / len2, t1 = (cz - a).dot(d) / len2;
        double lo = std::max(0.0, std::min(t0, t1)), hi = std::min(1.0, std::max(t0, t1));
        if (hi - lo > 1e-9) {
          iv.push_back({lo, hi});
          who.push_back(c);
        }
      }
    }
    std::vector<double> ts{0, 1};
    for (auto& i : iv) ts.insert(ts.end(), {i.first, i.second});
    std::sort(ts.begin(), ts.end());
    for (size_t i = 0; i + 1 < ts.size(); ++i) {
      if (ts[i + 1] - ts[i] < 1e-9) continue;
      double mid = 0.5 * (ts[i] + ts[i + 1]);
      int nb = -1;
      for (size_t k = 0; k < iv.size(); ++k)
        if (mid > iv[k].first && mid < iv[k].second) nb = who[k];
      out.push_back({a + d * ts[i], a + d * ts[i + 1], nb});
    }
  }
  return out;
}

// Joins boundary segments into one counter-clockwise ring without collinear vertices.
Ring2 chain(std::vector<std::pair<Vec2, Vec2>> segs) {
  Ring2 ring;
  if (segs.empty()) return ring;
  ring.push_back(segs.front().first);
  Vec2 cur = segs.front().second;
  segs.erase(segs.begin());
  while (!segs.empty()) {
    auto it = std::find_if(segs.begin(), segs.end(),
                           [&](const auto& s) { return (s.first - cur).norm() < 1e-7; });
    if (it == segs.end()) break;
    ring.push_back(it->first);
    cur = it->second;
    segs.erase(it);
  }
  Ring2 out;
  for (size_t i = 0, n = ring.size(); i < n; ++i) {
    Vec2 a = ring[(i + n - 1) % n], b = ring[i], c = ring[(i + 1) % n];
    Vec2 u = b - a, v = c - b;
    if (std::abs(u.x() * v.y() - u.y() * v.x()) > 1e-9 * u.norm() * v.norm()) out.push_back(b);
  }
  return out;
}

Element make_element(ElementType t, std::vector<Face> faces) {
  Element e;
  e.type = t;
  e.faces = std::move(faces);
  return e;
}

// Area, plan area, slope, azimuth from the faces (same rules as core/measure.h).
void measure(Element& e) {
  e.area = e.plan_area = 0;
  for (const auto& f : e.faces) {
    e.area += area(f);
    e.plan_area += plan_area(f);
  }
  if (e.type == ElementType::OuterCeiling) e.area = e.plan_area;
  if (e.faces.empty()) return;
  Vec3 n = unit_normal(e.faces.front());
  e.slope_deg = std::acos(std::min(1.0, std::abs(n.z()))) * 180 / kPi;
  double az = std::atan2(n.x(), n.y()) * 180 / kPi;
  e.azimuth_deg = e.slope_deg < 0.01 ? 0.0 : (az < 0 ? az + 360 : az);
}

// Elements, solid, footprint and heights of every building of a group, in the
// group frame with the ground floor at z = 0.
std::vector<TruthBuilding> assemble(const Group& g) {
  const auto pieces = roof_pieces(g);
  std::vector<TruthBuilding> out(g.owners);
  std::vector<std::vector<std::pair<Vec2, Vec2>>> outline(g.owners);
  for (int k = 0; k < g.owners; ++k) {
    out[k].roof_type = g.roof_type;
    out[k].model.id = "b" + std::to_string(k);
    out[k].wall_top_height = 1e300;
  }
  // Roof planes, outer ceiling, roof part inside the walls.
  std::map<std::pair<int, int>, std::vector<Face>> roof;
  std::vector<std::vector<Face>> ceiling(g.owners);
  for (const Piece& pc : pieces) {
    int owner = g.blocks[pc.block].owner;
    roof[{pc.block, pc.plane}].push_back({lift(pc.poly, *pc.pl), {}});
    std::vector<Ring2> rest{pc.poly};
    for (const Block& B : g.blocks) {
      std::vector<Ring2> next;
      for (const auto& r : rest)
        for (auto& s : subtract(r, B.footprint.ring())) next.push_back(std::move(s));
      rest = std::move(next);
      if (B.owner != owner) continue;
      Ring2 in = intersect(pc.poly, B.footprint.ring());
      if (poly_area(in) > kAreaEps) out[owner].model.solid.push_back({lift(in, *pc.pl), {}});
    }
    for (const auto& r : rest) {
      Ring3 down = lift(r, *pc.pl);
      std::reverse(down.begin(), down.end());
      ceiling[owner].push_back({down, {}});
    }
  }
  for (auto& [key, faces] : roof)
    out[g.blocks[key.first].owner].model.elements.push_back(
        make_element(ElementType::Roof, std::move(faces)));
  // Walls along every footprint edge part.
  for (int b = 0; b < int(g.blocks.size()); ++b) {
    const int owner = g.blocks[b].owner;
    TruthBuilding& tb = out[owner];
    for (const EdgePart& ep : edge_parts(g, b)) {
      Vec2 d = (ep.p1 - ep.p0).normalized();
      Vec2 inward(-d.y(), d.x());
      auto top = roof_profile(pieces, ep.p0, ep.p1, inward);
      int nb_owner = ep.neighbour < 0 ? -1 : g.blocks[ep.neighbour].owner;
      if (nb_owner != owner) outline[owner].push_back({ep.p0, ep.p1});
      if (nb_owner == owner) {  // step between two roof levels of one building
        auto bottom = roof_profile(pieces, ep.p0, ep.p1, -inward);
        auto [lo, hi] = height_gap(top, bottom);
        if (hi < 1e-7) continue;  // continuous roof, or the other part owns the step
        if (lo < -1e-7) throw std::logic_error("sample town: crossing roof step");
        Element w = make_element(ElementType::Wall, {vertical_face(ep.p0, ep.p1, bottom, top)});
        tb.model.solid.push_back(w.faces.front());
        tb.model.elements.push_back(std::move(w));
        continue;
      }
      std::vector<Vec2> base{{0, 0}, {1, 0}};
      ElementType type = nb_owner < 0 ? ElementType::Wall : ElementType::PartyWall;
      Element w = make_element(type, {vertical_face(ep.p0, ep.p1, base, top)});
      tb.model.solid.push_back(w.faces.front());
      tb.model.elements.push_back(std::move(w));
      if (nb_owner >= 0) {
        std::string other = "b" + std::to_string(nb_owner);
        if (std::find(tb.attached_to.begin(), tb.attached_to.end(), other) == tb.attached_to.end())
          tb.attached_to.push_back(other);
      } else {
        for (const auto& tz : top) tb.wall_top_height = std::min(tb.wall_top_height, tz.y());
      }
    }
  }
  // Ground faces (facing down) and per-building totals.
  std::vector<std::vector<Face>> ground(g.owners);
  for (const Block& B : g.blocks) {
    Ring3 r = lift(B.footprint.ring(), Plane{});
    std::reverse(r.begin(), r.end());
    ground[B.owner].push_back({r, {}});
    out[B.owner].model.solid.push_back({r, {}});
  }
  for (int k = 0; k < g.owners; ++k) {
    Building& m = out[k].model;
    m.elements.push_back(make_element(ElementType::Ground, std::move(ground[k])));
    if (!ceiling[k].empty())
      m.elements.push_back(make_element(ElementType::OuterCeiling, std::move(ceiling[k])));
    double lo = 1e300, hi = -1e300;
    for (const auto& e : m.elements)
      if (e.type == ElementType::Roof)
        for (const auto& f : e.faces)
          for (const auto& p : f.ring) lo = std::min(lo, p.z()), hi = std::max(hi, p.z());
    m.eave_height = lo;
    m.ridge_height = hi;
    m.volume = shell_volume(m.solid);
    m.solid_valid = shell_is_closed(m.solid, &m.solid_problem) && m.volume > 0;
    out[k].footprint = chain(outline[k]);
    for (auto& e : m.elements) measure(e);
  }
  return out;
}

// ---- Layout builders: BuildingParams -> blocks ----

std::vector<Plane> gable_planes(double u0, double u1, double v0, double v1, double he, double t,
                                bool hip) {
  std::vector<Plane> p{{0, t, he - t * v0}, {0, -t, he + t * v1}};
  if (hip) {
    p.push_back({t, 0, he - t * u0});
    p.push_back({-t, 0, he + t * u1});
  }
  return p;
}

Rect grow(const Rect& r, double w, double e, double s, double n) {
  return {r.u0 - w, r.u1 + e, r.v0 - s, r.v1 + n};
}

Group build_group(const BuildingParams& p) {
  Group g;
  g.roof_type = to_string(p.layout);
  const double L = p.length, W = p.width, o = p.overhang, he = p.eave_height;
  const double t = std::tan(p.pitch_deg * kPi / 180);
  const Rect main{0, L, 0, W};
  switch (p.layout) {
    case SampleLayout::Gable:
    case SampleLayout::Hip:
      g.blocks.push_back({main, grow(main, o, o, o, o),
                          gable_planes(0, L, 0, W, he, t, p.layout == SampleLayout::Hip), 0});
      break;
    case SampleLayout::Shed:
      g.blocks.push_back({main, grow(main, o, o, o, o), {{0, t, he}}, 0});
      break;
    case SampleLayout::Flat:
      g.blocks.push_back({main, grow(main, o, o, o, o), {{0, 0, he}}, 0});
      break;
    case SampleLayout::CrossGable: {
      g.blocks.push_back({main, grow(main, o, o, o, o), gable_planes(0, L, 0, W, he, t, false), 0});
      Rect wing{L - W, L, -p.wing_length, 0};
      // The wing roof reaches the main ridge: valleys where both roofs meet.
      Rect reg{L - W - o, L + o, -p.wing_length - o, W / 2};
      g.blocks.push_back({wing, reg, {{t, 0, he - t * (L - W)}, {-t, 0, he + t * L}}, 0});
      break;
    }
    case SampleLayout::TwoLevel: {
      g.blocks.push_back({main, grow(main, o, 0, o, o), gable_planes(0, L, 0, W, he, t, false), 0});
      Rect annex{L, L + p.annex_length, p.annex_inset, W - p.annex_inset};
      double ta = std::tan(p.annex_pitch_deg * kPi / 180);
      g.blocks.push_back({annex, grow(annex, 0, o, o, o), {{-ta, 0, p.annex_height + ta * L}}, 0});
      break;
    }
    case SampleLayout::RowHouse: {
      double u = 0;
      int n = int(p.house_widths.size());
      for (int k = 0; k < n; ++k) {
        Rect f{u, u + p.house_widths[k], 0, W};
        g.blocks.push_back({f, grow(f, k == 0 ? o : 0, k == n - 1 ? o : 0, o, o),
                            gable_planes(0, 0, 0, W, he, t, false), k});
        u += p.house_widths[k];
      }
      g.owners = n;
      break;
    }
    case SampleLayout::Empty: g.owners = 0; break;
  }
  return g;
}

}  // namespace

std::vector<TruthBuilding> make_truth_buildings(const BuildingParams& p) {
  auto out = assemble(build_group(p));
  for (auto& b : out) b.params = p;
  return out;
}

// ---- Shell checks ----

namespace {
using Key = std::array<long long, 3>;
Key key_of(const Vec3& p) {
  return {std::llround(p.x() * 1e6), std::llround(p.y() * 1e6), std::llround(p.z() * 1e6)};
}
}  // namespace

bool shell_is_closed(const std::vector<Face>& shell, std::string* problem) {
  std::vector<Vec3> verts;
  for (const auto& f : shell) verts.insert(verts.end(), f.ring.begin(), f.ring.end());
  std::map<std::pair<Key, Key>, int> edges;
  for (const auto& f : shell) {
    const Ring3 r = dedupe(f.ring);
    for (size_t i = 0, n = r.size(); i < n; ++i) {
      const Vec3 a = r[i], b = r[(i + 1) % n];
      const Vec3 d = b - a;
      double len2 = d.squaredNorm();
      // Split the edge at every shell vertex lying inside it (T-junctions).
      std::vector<std::pair<double, Vec3>> cuts{{0, a}, {1, b}};
      for (const auto& v : verts) {
        double t = (v - a).dot(d) / len2;
        if (t > 1e-9 && t < 1 - 1e-9 && (a + d * t - v).norm() < 1e-6) cuts.push_back({t, v});
      }
      std::sort(cuts.begin(), cuts.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
      for (size_t k = 0; k + 1 < cuts.size(); ++k) {
        Key ka = key_of(cuts[k].second), kb = key_of(cuts[k + 1].second);
        if (ka != kb) ++edges[{ka, kb}];
      }
    }
  }
  for (const auto& [e, n] : edges) {
    auto rev = edges.find({e.second, e.first});
    int m = rev == edges.end() ? 0 : rev->second;
    if (n != 1 || m != 1) {
      if (problem) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "edge (%.3f %.3f %.3f)-(%.3f %.3f %.3f) used %d+%d times",
                      e.first[0] * 1e-6, e.first[1] * 1e-6, e.first[2] * 1e-6, e.second[0] * 1e-6,
                      e.second[1] * 1e-6, e.second[2] * 1e-6, n, m);
        *problem = buf;
      }
      return false;
    }
  }
  if (problem) problem->clear();
  return !edges.empty();
}

double shell_volume(const std::vector<Face>& shell) {
  if (shell.empty() || shell.front().ring.empty()) return 0;
  const Vec3 o = shell.front().ring.front();
  double v = 0;
  for (const auto& f : shell)
    for (size_t i = 1; i + 1 < f.ring.size(); ++i)
      v += (f.ring[0] - o).dot((f.ring[i] - o).cross(f.ring[i + 1] - o));
  return v / 6;
}

// ---- The town ----

namespace {

constexpr int kPerRow = 5;          // parcels along a block side
constexpr double kBlockWidth = 100; // m, along the street
constexpr double kStreet = 10;      // m
constexpr double kMaxDepth = 32;    // m, parcel depth upper bound

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

// Terrain: gentle slope plus two undulations; local xy -> world z.
struct Terrain {
  double z0, gx, gy, a1, l1, l2, ph1, ph2, a2, l3, ph3;
  explicit Terrain(Rng& r)
      : z0(r.uniform(700, 760)), gx(r.uniform(-0.02, 0.02)), gy(r.uniform(-0.02, 0.02)),
        a1(r.uniform(0.5, 1.5)), l1(r.uniform(150, 400)), l2(r.uniform(150, 400)),
        ph1(r.uniform(0, 2 * kPi)), ph2(r.uniform(0, 2 * kPi)), a2(r.uniform(0.2, 0.6)),
        l3(r.uniform(60, 120)), ph3(r.uniform(0, 2 * kPi)) {}
  double operator()(double x, double y) const {
    return z0 + gx * x + gy * y + a1 * std::sin(2 * kPi * x / l1 + ph1) * std::cos(2 * kPi * y / l2 + ph2) +
           a2 * std::sin(2 * kPi * (x + y) / l3 + ph3);
  }
};

struct TownParcel {
  Rect rect;        // town frame (s along the street, t across)
  bool north_row;   // front on the north street
};

// Parcel rectangles in the town frame, layer order: block by block, south row
// west to east, then north row.
std::vector<TownParcel> lay_out_parcels(int n, Rng& rng) {
  std::vector<TownParcel> out;
  int blocks = (n + 2 * kPerRow - 1) / (2 * kPerRow);
  int cols = std::max(1, int(std::ceil(std::sqrt(double(blocks)))));
  for (int b = 0; b < blocks; ++b) {
    double s0 = (b % cols) * (kBlockWidth + kStreet), t0 = (b / cols) * (2 * kMaxDepth + kStreet);
    double depth[2] = {rng.uniform(26, kMaxDepth), rng.uniform(26, kMaxDepth)};
    for (int row = 0; row < 2; ++row) {
      double w[kPerRow], sum = 0;
      for (double& x : w) sum += (x = rng.uniform(0.85, 1.15));
      double s = s0;
      double ta = row == 0 ? t0 : t0 + depth[0], tb = ta + depth[row];
      for (int k = 0; k < kPerRow && int(out.size()) < n; ++k) {
        double ds = kBlockWidth * w[k] / sum;
        out.push_back({{s, s + ds, ta, tb}, row == 1});
        s += ds;
      }
    }
  }
  return out;
}

// Which layout each parcel gets; a row of attached houses spans 2-3 parcels of one
// block side. Every layout appears within the first 10 parcels.
std::vector<std::pair<SampleLayout, int>> assign_layouts(int n) {
  static const SampleLayout cycle[] = {SampleLayout::Gable,    SampleLayout::Hip,
                                       SampleLayout::CrossGable, SampleLayout::Shed,
                                       SampleLayout::Flat,     SampleLayout::TwoLevel,
                                       SampleLayout::RowHouse, SampleLayout::Empty};
  std::vector<std::pair<SampleLayout, int>> out;  // (layout, houses in the row starting here)
  int slot = 0, rows = 0;
  for (int i = 0; i < n;) {
    SampleLayout l = cycle[slot % 8];
    int left_in_side = std::min(kPerRow - i % kPerRow, n - i);
    if (l == SampleLayout::RowHouse) {
      int m = rows % 2 == 0 ? 3 : 2;
      if (left_in_side < m) m = 2;
      if (left_in_side < m) {  // no room on this block side: a gable now, the row later
        out.push_back({SampleLayout::Gable, 1});
        ++i;
        continue;
      }
      for (int k = 0; k < m; ++k) out.push_back({l, k == 0 ? m : 0});
      i += m;
      ++rows;
    } else {
      out.push_back({l, 1});
      ++i;
    }
    ++slot;
  }
  return out;
}

BuildingParams random_params(SampleLayout l, Rng& r) {
  BuildingParams p;
  p.layout = l;
  p.overhang = r.uniform(0.3, 0.8);
  p.pitch_deg = r.uniform(22, 40);
  p.eave_height = r.chance(0.5) ? r.uniform(3.0, 3.4) : r.uniform(6.0, 6.6);
  p.length = r.uniform(10, 15);
  p.width = r.uniform(7, 9.5);
  switch (l) {
    case SampleLayout::Shed:
      p.length = r.uniform(8, 12), p.width = r.uniform(6, 8), p.pitch_deg = r.uniform(8, 15);
      p.eave_height = r.uniform(3.0, 3.5);
      break;
    case SampleLayout::Flat: p.eave_height = r.uniform(3.0, 7.0); break;
    case SampleLayout::CrossGable:
      p.length = r.uniform(12, 16), p.width = r.uniform(6.5, 8.5), p.wing_length = r.uniform(3.5, 6);
      break;
    case SampleLayout::TwoLevel:
      p.length = r.uniform(9, 12), p.width = r.uniform(7, 9), p.eave_height = r.uniform(5.8, 6.5);
      p.annex_length = r.uniform(3, 5), p.annex_inset = r.uniform(0.5, 1.5);
      p.annex_height = r.uniform(2.8, 3.4);
      p.annex_pitch_deg = r.chance(0.5) ? 0.0 : r.uniform(5, 10);
      break;
    default: break;
  }
  return p;
}

void scale_lengths(BuildingParams& p, double s) {
  for (double* x : {&p.length, &p.width, &p.wing_length, &p.annex_length, &p.annex_inset}) *x *= s;
}

Rect bbox(const Group& g, bool regions) {
  Rect b{1e300, -1e300, 1e300, -1e300};
  for (const auto& B : g.blocks) {
    const Rect& r = regions ? B.region : B.footprint;
    b = {std::min(b.u0, r.u0), std::max(b.u1, r.u1), std::min(b.v0, r.v0), std::max(b.v1, r.v1)};
  }
  return b;
}

// A detached building: arbitrary rotation, shrunk until it fits its parcel with
// a 1 m margin, placed off-centre by chance. town_angle rotates town -> local.
Placement place_detached(BuildingParams& p, const Rect& parcel, double town_angle, Rng& r) {
  double th = r.uniform(0, kPi);
  double c = std::abs(std::cos(th)), s = std::abs(std::sin(th));
  Rect f = bbox(build_group(p), false);
  double du = f.u1 - f.u0, dv = f.v1 - f.v0, oo = 2 * p.overhang * (c + s);
  double aw = parcel.u1 - parcel.u0 - 2, ad = parcel.v1 - parcel.v0 - 2;
  double k = std::min({1.0, (aw - oo) / (du * c + dv * s), (ad - oo) / (du * s + dv * c)});
  if (k < 1) scale_lengths(p, k * 0.999);
  Rect rg = bbox(build_group(p), true);
  double ru = rg.u1 - rg.u0, rv = rg.v1 - rg.v0;
  double ex = ru * c + rv * s, ey = ru * s + rv * c;
  Vec2 mid((parcel.u0 + parcel.u1) / 2, (parcel.v0 + parcel.v1) / 2);
  mid += Vec2(r.uniform(-0.5, 0.5) * std::max(0.0, aw - ex), r.uniform(-0.5, 0.5) * std::max(0.0, ad - ey));
  Vec2 rc((rg.u0 + rg.u1) / 2, (rg.v0 + rg.v1) / 2);
  Placement town{mid, th};
  Vec2 origin_town = mid - (town.to_local(rc) - mid);  // group origin in the town frame
  Placement toloc{Vec2::Zero(), town_angle};
  return {toloc.to_local(origin_town), th + town_angle};
}

// Attached houses on parcels [first, first+m): party walls on the parcel lines.
Placement place_row(BuildingParams& p, const std::vector<TownParcel>& tp, int first, int m,
                    double town_angle, Rng& r) {
  p.layout = SampleLayout::RowHouse;
  p.width = r.uniform(8, 10);
  double margin = p.overhang + r.uniform(0.6, 1.5);
  double s_start = tp[first].rect.u0 + margin, s_end = tp[first + m - 1].rect.u1 - margin;
  p.house_widths.clear();
  for (int k = 0; k < m; ++k) {
    double a = k == 0 ? s_start : tp[first + k].rect.u0;
    double b = k == m - 1 ? s_end : tp[first + k].rect.u1;
    p.house_widths.push_back(b - a);
  }
  p.length = s_end - s_start;
  const Rect& pr = tp[first].rect;
  double setback = r.uniform(2.5, 5);
  double v0 = tp[first].north_row ? pr.v1 - setback - p.width : pr.v0 + setback;
  Placement toloc{Vec2::Zero(), town_angle};
  return {toloc.to_local(Vec2(s_start, v0)), town_angle};
}

// Moves the ground floor (every vertex at z = 0, group frame) to z = dz:
// ground faces and wall feet follow, the roof stays. Element areas are
// measured afterwards by transform().
void move_floor(TruthBuilding& tb, double dz) {
  if (dz == 0) return;
  auto shift = [&](Face& f) {
    for (auto& p : f.ring)
      if (p.z() == 0) p.z() = dz;
  };
  Building& m = tb.model;
  for (auto& e : m.elements)
    for (auto& f : e.faces) shift(f);
  for (auto& f : m.solid) shift(f);
  m.eave_height -= dz;
  m.ridge_height -= dz;
  tb.wall_top_height -= dz;
  m.volume = shell_volume(m.solid);
}

Vec3 place3(const Placement& pl, const Vec3& q, double dz) {
  Vec2 xy = pl.to_local(q.head<2>());
  return {xy.x(), xy.y(), q.z() + dz};
}

void transform(TruthBuilding& tb, const Placement& pl, double dz) {
  auto tf = [&](Face& f) {
    for (auto& p : f.ring) p = place3(pl, p, dz);
  };
  for (auto& e : tb.model.elements) {
    for (auto& f : e.faces) tf(f);
    measure(e);
  }
  for (auto& f : tb.model.solid) tf(f);
  for (auto& p : tb.footprint) p = pl.to_local(p);
  tb.model.terrain_z = dz;
}

Dtm make_dtm(const std::vector<Parcel>& parcels, const LocalFrame& frame, const Terrain& terrain,
             const std::string& wkt) {
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (const auto& p : parcels)
    for (const auto& v : p.shape.front().outer)
      x0 = std::min(x0, v.x()), x1 = std::max(x1, v.x()), y0 = std::min(y0, v.y()), y1 = std::max(y1, v.y());
  const double margin = 15;
  double wx0 = std::floor(x0 - margin), wx1 = std::ceil(x1 + margin);
  double wy0 = std::floor(y0 - margin), wy1 = std::ceil(y1 + margin);
  Dtm d;
  d.crs_wkt = wkt;
  d.source = "sample";
  d.nx = int(wx1 - wx0), d.ny = int(wy1 - wy0);
  d.x0 = wx0 + 0.5, d.y0 = wy1 - 0.5, d.dx = 1, d.dy = -1;
  d.z.resize(size_t(d.nx) * d.ny);
  for (int j = 0; j < d.ny; ++j)
    for (int i = 0; i < d.nx; ++i) {
      Vec2 l = frame.to_local(Vec2(d.x0 + i, d.y0 - j));
      d.z[size_t(j) * d.nx + i] = float(terrain(l.x(), l.y()));
    }
  return d;
}

// Mean DTM value over the cells whose centres fall in the footprints of the
// group's blocks owned by `owner` (-1: all blocks), world z; marks those cells NoData.
double ground_level(const Group& g, const Placement& pl, const LocalFrame& frame, const Dtm& d,
                    std::vector<std::uint8_t>& nodata, int owner = -1) {
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (const auto& B : g.blocks)
    for (const auto& q : B.footprint.ring()) {
      Vec2 w = frame.to_world(pl.to_local(q));
      x0 = std::min(x0, w.x()), x1 = std::max(x1, w.x()), y0 = std::min(y0, w.y()), y1 = std::max(y1, w.y());
    }
  int i0 = std::max(0, int(std::floor(x0 - d.x0))), i1 = std::min(d.nx - 1, int(std::ceil(x1 - d.x0)));
  int j0 = std::max(0, int(std::floor(d.y0 - y1))), j1 = std::min(d.ny - 1, int(std::ceil(d.y0 - y0)));
  double sum = 0;
  long n = 0;
  for (int j = j0; j <= j1; ++j)
    for (int i = i0; i <= i1; ++i) {
      Vec2 q = pl.to_group(frame.to_local(Vec2(d.x0 + i, d.y0 - j)));
      for (const auto& B : g.blocks)
        if ((owner < 0 || B.owner == owner) && B.footprint.contains(q)) {
          size_t idx = size_t(j) * d.nx + i;
          sum += d.z[idx];
          ++n;
          nodata[idx] = 1;
          break;
        }
    }
  if (n > 0) return sum / n;
  Vec2 c = frame.to_world(pl.to_local(g.blocks.front().footprint.ring().front()));
  return d.height_at(c.x(), c.y());
}

std::string nib(int k) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "102805030%05d", k + 1);
  return buf;
}

std::string wkt_of(int epsg) {
  OGRSpatialReference srs;
  if (srs.importFromEPSG(epsg) != OGRERR_NONE)
    throw std::runtime_error("sample: unknown EPSG code " + std::to_string(epsg));
  char* w = nullptr;
  srs.exportToWkt(&w);
  std::string s = w ? w : "";
  CPLFree(w);
  return s;
}

// ---- Point sampling ----

class Sampler {
 public:
  Sampler(SampleTown& town, Rng& rng) : t_(town), r_(rng) {}

  // Uniform points on a convex planar ring: fan triangles picked by area.
  void fan(const Ring3& ring) {
    double total = 0;
    cum_.clear();
    for (size_t i = 1; i + 1 < ring.size(); ++i)
      cum_.push_back(total += 0.5 * (ring[i] - ring[0]).cross(ring[i + 1] - ring[0]).norm());
  }
  Vec3 on_fan(const Ring3& ring) {
    double u = r_.uniform() * cum_.back();
    size_t k = std::min(size_t(std::lower_bound(cum_.begin(), cum_.end(), u) - cum_.begin()),
                        cum_.size() - 1);
    double s = std::sqrt(r_.uniform()), v = r_.uniform();
    return ring[0] * (1 - s) + ring[k + 1] * (s * (1 - v)) + ring[k + 2] * (s * v);
  }
  Vec3 on_face(const Ring3& ring) {
    fan(ring);
    return on_fan(ring);
  }
  void add(const Vec3& local, double sigma, std::uint8_t cls, PointTag tag) {
    Vec3 n(r_.normal(), r_.normal(), r_.normal());
    t_.cloud.points.push_back(t_.frame.to_world(Vec3(local + n * sigma)));
    t_.cloud.classes.push_back(cls);
    t_.point_tags.push_back(tag);
  }
  // Points on every face of an element; returns how many.
  int element(const Element& e, double density_per_plan_or_area, bool per_plan, double sigma,
              std::uint8_t cls, double outlier_share) {
    int n = 0;
    for (const auto& f : e.faces) {
      long k = r_.count(density_per_plan_or_area * (per_plan ? plan_area(f) : area(f)));
      if (k > 0) fan(f.ring);
      for (long i = 0; i < k; ++i, ++n) {
        Vec3 p = on_fan(f.ring);
        if (r_.chance(outlier_share)) {
          p.z() += (r_.chance(0.5) ? 1 : -1) * r_.uniform(0.5, 4.0);
          add(p, sigma, cls, PointTag::Outlier);
        } else {
          add(p, sigma, cls, PointTag::Surface);
        }
      }
    }
    return n;
  }
  // An antenna (vertical line) or a water tank (cylinder) standing on the roof.
  void clutter(const Face& roof, double density, double sigma) {
    Vec3 base = on_face(roof.ring);
    if (r_.chance(0.5)) {
      double h = r_.uniform(1.5, 3.0);
      for (int i = 0, n = int(h * 12); i < n; ++i)
        add(base + Vec3(0, 0, h * (i + 0.5) / n), sigma, 6, PointTag::Clutter);
      return;
    }
    double rad = r_.uniform(0.4, 0.7), h = r_.uniform(0.8, 1.4);
    long side = r_.count(density * 2 * kPi * rad * h), top = r_.count(density * kPi * rad * rad);
    for (long i = 0; i < side; ++i) {
      double a = r_.uniform(0, 2 * kPi);
      add(base + Vec3(rad * std::cos(a), rad * std::sin(a), r_.uniform(0, h)), sigma, 6, PointTag::Clutter);
    }
    for (long i = 0; i < top; ++i) {
      double a = r_.uniform(0, 2 * kPi), q = rad * std::sqrt(r_.uniform());
      add(base + Vec3(q * std::cos(a), q * std::sin(a), h), sigma, 6, PointTag::Clutter);
    }
  }

 private:
  SampleTown& t_;
  Rng& r_;
  std::vector<double> cum_;
};

bool inside_convex(const Ring3& r, const Vec2& p) {
  for (size_t i = 0, n = r.size(); i < n; ++i) {
    Vec2 a = r[i].head<2>(), b = r[(i + 1) % n].head<2>();
    if ((b - a).x() * (p - a).y() - (b - a).y() * (p - a).x() < 0) return false;
  }
  return true;
}

void sample_points(SampleTown& town, const SampleOptions& opt, Rng& rng,
                   const std::vector<TownParcel>& tp, double town_angle) {
  Sampler s(town, rng);
  double roof = 0, wall = 0, ground = 0;  // expected counts, to reserve once
  for (const auto& p : town.truth)
    for (const auto& tb : p) {
      BuildingTotals t = totals(tb.model);
      roof += t.roof_plan;
      wall += t.wall;
    }
  for (const auto& p : town.parcels) ground += area(p.shape);
  size_t expect = size_t(roof * opt.roof_density * 1.02 + wall * opt.wall_density +
                         ground * opt.ground_density) + 1000;
  town.cloud.points.reserve(expect);
  town.cloud.classes.reserve(expect);
  town.point_tags.reserve(expect);
  Placement toloc{Vec2::Zero(), town_angle};
  for (size_t pi = 0; pi < town.parcels.size(); ++pi) {
    for (auto& tb : town.truth[pi]) {
      Building& m = tb.model;
      const Face* biggest = nullptr;
      for (auto& e : m.elements) {
        if (e.type == ElementType::Roof) {
          e.support_points = s.element(e, opt.roof_density, true, opt.roof_noise, 6, opt.outlier_share);
          e.rmse = opt.roof_noise;
          for (const auto& f : e.faces)
            if (!biggest || area(f) > area(*biggest)) biggest = &f;
        } else if (e.type == ElementType::Wall) {
          if (rng.chance(opt.wall_occlusion)) continue;
          e.support_points = s.element(e, opt.wall_density, false, opt.wall_noise, 64, 0);
          e.rmse = opt.wall_noise;
          e.evidence = WallEvidence::Measured;
        }
      }
      if (biggest && rng.chance(opt.clutter_share)) s.clutter(*biggest, opt.roof_density, opt.roof_noise);
    }
    // Open ground of the parcel, outside every roof over it.
    const Rect& r = tp[pi].rect;
    long k = rng.count(opt.ground_density * (r.u1 - r.u0) * (r.v1 - r.v0));
    for (long i = 0; i < k; ++i) {
      Vec2 p = toloc.to_local(Vec2(rng.uniform(r.u0, r.u1), rng.uniform(r.v0, r.v1)));
      bool covered = false;
      for (const auto& tb : town.truth[pi])
        for (const auto& e : tb.model.elements)
          if (e.type == ElementType::Roof)
            for (const auto& f : e.faces) covered = covered || inside_convex(f.ring, p);
      if (covered) continue;
      Vec2 w = town.frame.to_world(p);
      s.add(Vec3(p.x(), p.y(), town.dtm.height_at(w.x(), w.y()) - town.frame.origin.z()),
            opt.roof_noise, 2, PointTag::Surface);
    }
    if (opt.progress && (pi % 100 == 99 || pi + 1 == town.parcels.size()))
      opt.progress("points", int(pi + 1), int(town.parcels.size()));
  }
}

}  // namespace

SampleTown make_sample_town(const SampleOptions& opt) {
  if (opt.parcels < 1) throw std::invalid_argument("sample: --parcels must be at least 1");
  SampleTown town;
  town.seed = opt.seed;
  town.epsg = opt.epsg;
  town.crs_wkt = wkt_of(opt.epsg);
  Rng rng(opt.seed);
  const Terrain terrain(rng);
  const double town_angle = rng.uniform(-25, 25) * kPi / 180;
  town.frame.origin = Vec3(opt.origin_easting, opt.origin_northing, std::round(terrain.z0));
  const auto tp = lay_out_parcels(opt.parcels, rng);
  const auto layouts = assign_layouts(opt.parcels);
  Placement toloc{Vec2::Zero(), town_angle};
  for (size_t i = 0; i < tp.size(); ++i) {
    Parcel p;
    p.index = int(i);
    p.id = nib(int(i));
    p.right_type = rng.chance(0.7) ? "Hak Milik" : "Hak Guna Bangunan";
    Polygon2 poly;
    for (const auto& q : tp[i].rect.ring()) poly.outer.push_back(town.frame.to_world(toloc.to_local(q)));
    p.shape = {poly};
    // Certificates carry a rounded, slightly different area (older survey).
    p.official_area = std::round(area(p.shape) * (1 + 0.01 * rng.normal()));
    town.parcels.push_back(std::move(p));
    town.layouts.push_back(layouts[i].first);
  }
  town.dtm = make_dtm(town.parcels, town.frame, terrain, town.crs_wkt);
  town.dtm_nodata.assign(town.dtm.z.size(), 0);
  town.truth.resize(tp.size());
  for (size_t i = 0; i < tp.size(); ++i) {
    auto [layout, houses] = layouts[i];
    if (layout == SampleLayout::Empty || houses == 0) continue;
    BuildingParams bp = random_params(layout, rng);
    Placement pl = layout == SampleLayout::RowHouse
                       ? place_row(bp, tp, int(i), houses, town_angle, rng)
                       : place_detached(bp, tp[i].rect, town_angle, rng);
    Group g = build_group(bp);
    double level = ground_level(g, pl, town.frame, town.dtm, town.dtm_nodata);
    auto buildings = assemble(g);
    for (size_t k = 0; k < buildings.size(); ++k) {
      TruthBuilding& tb = buildings[k];
      tb.params = bp;
      // Attached houses share one roof but each floor follows its own terrain.
      double own = buildings.size() > 1
                       ? ground_level(g, pl, town.frame, town.dtm, town.dtm_nodata, int(k))
                       : level;
      move_floor(tb, own - level);
      tb.ground_level = own;
      transform(tb, pl, level - town.frame.origin.z());
      tb.model.terrain_z = own - town.frame.origin.z();
      tb.model.id = nib(int(i + k)) + "_b0";
      for (auto& a : tb.attached_to) a = nib(int(i) + std::stoi(a.substr(1))) + "_b0";
      town.truth[i + k].push_back(std::move(tb));
    }
    if (opt.progress && (i % 100 == 99 || i + 1 == tp.size()))
      opt.progress("buildings", int(i + 1), int(tp.size()));
  }
  long cells = 0;
  for (auto v : town.dtm_nodata) cells += v;
  town.dtm.nodata_share = town.dtm.z.empty() ? 0 : double(cells) / town.dtm.z.size();
  town.cloud.source = "sample";
  town.cloud.crs_wkt = town.crs_wkt;
  if (opt.with_points) sample_points(town, opt, rng, tp, town_angle);
  return town;
}

// ---- Files ----

namespace {

double r6(double x) { return std::round(x * 1e6) / 1e6; }

nlohmann::ordered_json building_json(const TruthBuilding& tb, const LocalFrame& frame) {
  const Building& m = tb.model;
  BuildingTotals t = totals(m);
  nlohmann::ordered_json j;
  j["building_id"] = m.id;
  j["roof_type"] = tb.roof_type;
  j["overhang_m"] = r6(tb.params.overhang);
  j["pitch_deg"] = r6(tb.params.layout == SampleLayout::Flat ? 0.0 : tb.params.pitch_deg);
  j["ground_level_m"] = r6(tb.ground_level);
  j["roof_area_m2"] = r6(t.roof);
  j["roof_plan_area_m2"] = r6(t.roof_plan);
  j["wall_area_m2"] = r6(t.wall);
  j["party_wall_area_m2"] = r6(t.party_wall);
  j["ground_area_m2"] = r6(t.ground);
  j["outer_ceiling_area_m2"] = r6(t.outer_ceiling);
  j["volume_m3"] = r6(m.volume);
  j["eave_height_m"] = r6(m.eave_height);
  j["wall_top_height_m"] = r6(tb.wall_top_height);
  j["ridge_height_m"] = r6(m.ridge_height);
  j["roof_planes"] = t.roof_planes;
  j["attached_to"] = tb.attached_to;
  auto planes = nlohmann::ordered_json::array();
  for (const auto& e : m.elements)
    if (e.type == ElementType::Roof)
      planes.push_back({{"area_m2", r6(e.area)}, {"plan_area_m2", r6(e.plan_area)},
                        {"slope_deg", r6(e.slope_deg)}, {"azimuth_deg", r6(e.azimuth_deg)},
                        {"points", e.support_points}});
  j["roof_plane_details"] = planes;
  auto fp = nlohmann::ordered_json::array();
  for (const auto& p : tb.footprint) {
    Vec2 w = frame.to_world(p);
    fp.push_back({r6(w.x()), r6(w.y())});
  }
  j["footprint"] = fp;
  return j;
}

void write_parcels(const SampleTown& town, const std::string& path, ParcelFormat format) {
  register_gdal_drivers();
  const char* drv_name = format == ParcelFormat::GeoPackage ? "GPKG" : "GeoJSON";
  GDALDriver* drv = GetGDALDriverManager()->GetDriverByName(drv_name);
  if (!drv) throw std::runtime_error(std::string("GDAL driver missing: ") + drv_name);
  std::filesystem::remove(path);
  GdalDataset ds(drv->Create(path.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
  if (!ds) throw std::runtime_error(path + ": cannot create");
  OGRSpatialReference srs;
  srs.importFromEPSG(town.epsg);
  srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  OGRLayer* layer = ds->CreateLayer("parcels", &srs, wkbPolygon, nullptr);
  if (!layer) throw std::runtime_error(path + ": cannot create layer");
  OGRFieldDefn nib_f("NIB", OFTString), hak("TIPEHAK", OFTString), luas("LUASTERTUL", OFTReal),
      peta("LUASPETA", OFTReal);
  for (auto* f : {&nib_f, &hak, &luas, &peta}) layer->CreateField(f);
  ds->StartTransaction();
  for (const auto& p : town.parcels) {
    OGRFeature feat(layer->GetLayerDefn());
    feat.SetField("NIB", p.id.c_str());
    feat.SetField("TIPEHAK", p.right_type.c_str());
    feat.SetField("LUASTERTUL", p.official_area);
    feat.SetField("LUASPETA", std::round(area(p.shape)));
    OGRPolygon poly;
    OGRLinearRing ring;
    for (const auto& v : p.shape.front().outer) ring.addPoint(v.x(), v.y());
    ring.closeRings();
    poly.addRing(&ring);
    feat.SetGeometry(&poly);
    if (layer->CreateFeature(&feat) != OGRERR_NONE) throw std::runtime_error(path + ": write failed");
  }
  ds->CommitTransaction();
}

void write_dtm(const SampleTown& town, const std::string& path) {
  register_gdal_drivers();
  GDALDriver* drv = GetGDALDriverManager()->GetDriverByName("GTiff");
  const Dtm& d = town.dtm;
  const char* opts[] = {"COMPRESS=DEFLATE", "TILED=YES", nullptr};
  GdalDataset ds(
      drv->Create(path.c_str(), d.nx, d.ny, 1, GDT_Float32, const_cast<char**>(opts)));
  if (!ds) throw std::runtime_error(path + ": cannot create");
  double gt[6] = {d.x0 - 0.5, d.dx, 0, d.y0 + 0.5, 0, d.dy};
  ds->SetGeoTransform(gt);
  ds->SetProjection(town.crs_wkt.c_str());
  std::vector<float> z = d.z;
  const float nodata = -9999.f;
  for (size_t i = 0; i < z.size(); ++i)
    if (town.dtm_nodata[i]) z[i] = nodata;
  GDALRasterBand* band = ds->GetRasterBand(1);
  band->SetNoDataValue(nodata);
  if (band->RasterIO(GF_Write, 0, 0, d.nx, d.ny, z.data(), d.nx, d.ny, GDT_Float32, 0, 0) != CE_None)
    throw std::runtime_error(path + ": write failed");
}

}  // namespace

std::string truth_json(const SampleTown& town) {
  nlohmann::ordered_json j;
  j["generator"] = "cadastre3d sample";
  j["seed"] = town.seed;
  j["epsg"] = town.epsg;
  j["local_origin"] = {town.frame.origin.x(), town.frame.origin.y(), town.frame.origin.z()};
  j["conventions"] = {
      {"ground_level", "mean of the 1 m DTM cells whose centres lie in the footprint; walls start there"},
      {"wall", "exterior walls from the ground level to the roof plane at the wall line, gables and roof steps included"},
      {"party_wall", "full shared face, reported by each of the two attached houses"},
      {"outer_ceiling", "roof plan area minus footprint"},
      {"eave_height", "lowest roof vertex above ground level (overhang edge)"},
      {"wall_top_height", "lowest point where an exterior wall meets the roof"}};
  auto parcels = nlohmann::ordered_json::array();
  for (size_t i = 0; i < town.parcels.size(); ++i) {
    const Parcel& p = town.parcels[i];
    nlohmann::ordered_json pj;
    pj["parcel_id"] = p.id;
    pj["right_type"] = p.right_type;
    pj["layout"] = to_string(town.layouts[i]);
    pj["polygon_area_m2"] = r6(area(p.shape));
    pj["official_area_m2"] = p.official_area;
    auto bs = nlohmann::ordered_json::array();
    for (const auto& tb : town.truth[i]) bs.push_back(building_json(tb, town.frame));
    pj["buildings"] = bs;
    parcels.push_back(pj);
  }
  j["parcels"] = parcels;
  return j.dump(1);
}

SampleFiles write_sample_town(const SampleTown& town, const std::string& dir, ParcelFormat format) {
  namespace fs = std::filesystem;
  fs::create_directories(dir);
  SampleFiles f;
  f.parcels = (fs::path(dir) / (format == ParcelFormat::GeoPackage ? "parcels.gpkg" : "parcels.geojson")).string();
  f.dtm = (fs::path(dir) / "dtm.tif").string();
  f.truth = (fs::path(dir) / "truth.json").string();
  write_parcels(town, f.parcels, format);
  write_dtm(town, f.dtm);
  if (!town.cloud.points.empty()) {
    f.cloud = (fs::path(dir) / "cloud.las").string();
    write_las(f.cloud, town.cloud, 6, 4);
  }
  std::ofstream(f.truth) << truth_json(town) << "\n";
  return f;
}

}  // namespace c3d
