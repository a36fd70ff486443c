// Building groups -> exact truth buildings: roof pieces (lower envelope of the
// block planes, higher roof wins where blocks overlap), walls along the
// footprint edges, ground faces, outer ceiling, heights and the closed solid.
#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include "core/geometry/geometry.h"
#include "core/synthetic/sample_detail.h"

namespace c3d {

using namespace sample_detail;

namespace {

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

}  // namespace

void sample_detail::measure(Element& e) {
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

namespace {

// Roof planes, outer ceiling, roof part inside the walls.
void add_roofs(const Group& g, const std::vector<Piece>& pieces, std::vector<TruthBuilding>& out,
               std::vector<std::vector<Face>>& ceiling) {
  std::map<std::pair<int, int>, std::vector<Face>> roof;
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
}

// Walls along every footprint edge part; outline collects each building's
// outer edges.
void add_walls(const Group& g, const std::vector<Piece>& pieces, std::vector<TruthBuilding>& out,
               std::vector<std::vector<std::pair<Vec2, Vec2>>>& outline) {
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
}

// Ground faces (facing down) and per-building totals.
void finish_buildings(const Group& g, std::vector<TruthBuilding>& out,
                      std::vector<std::vector<Face>>& ceiling,
                      const std::vector<std::vector<std::pair<Vec2, Vec2>>>& outline) {
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
}

}  // namespace

std::vector<TruthBuilding> sample_detail::assemble(const Group& g) {
  const auto pieces = roof_pieces(g);
  std::vector<TruthBuilding> out(g.owners);
  std::vector<std::vector<std::pair<Vec2, Vec2>>> outline(g.owners);
  for (int k = 0; k < g.owners; ++k) {
    out[k].roof_type = g.roof_type;
    out[k].model.id = "b" + std::to_string(k);
    out[k].wall_top_height = 1e300;
  }
  std::vector<std::vector<Face>> ceiling(g.owners);
  add_roofs(g, pieces, out, ceiling);
  add_walls(g, pieces, out, outline);
  finish_buildings(g, out, ceiling, outline);
  return out;
}

// ---- Layout builders: BuildingParams -> blocks ----

namespace {

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

}  // namespace

Group sample_detail::build_group(const BuildingParams& p) {
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

std::vector<TruthBuilding> make_truth_buildings(const BuildingParams& p) {
  if (is_curved(p.layout)) return {make_curved_building(p)};
  auto out = assemble(build_group(p));
  for (auto& b : out) b.params = p;
  return out;
}

}  // namespace c3d
