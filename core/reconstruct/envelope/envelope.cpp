#include "core/reconstruct/envelope/envelope.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <optional>
#include <stdexcept>
#include <cstdio>
#include <cstdlib>
#include <tuple>

#include "core/geometry/geometry.h"
#include "core/log.h"
#include "core/reconstruct/outline/outline.h"
#include "core/geometry/polygon_ops.h"

namespace c3d {
namespace {

Vec2 outward(const Vec2& d) { return Vec2(d.y(), -d.x()); }  // for counter-clockwise rings

// Wall points further inside a roof edge than this belong to another wall
// (an inner facade, a neighbour): hanging roofs reach about 1.5 m.
constexpr double kMaxOverhang = 1.8;
// A measured overhang this much larger than the building's typical one, and
// than its facade's (facade_overhang), is taken as a misread (another wall
// behind the edge) and replaced by the facade's. A wall
// found closer to the edge is believed: gable ends and walls under a lower
// roof often have little or no overhang.
constexpr double kOverhangOutlier = 0.6;
// A wall seen up to this far outside the roof outline is the wall under that
// edge, flush with the eave: the outline (a hull of roof points) stops short of
// the true eave where the eave's points are missing. Farther out stands
// something else (a fence, a neighbour across a gap).
constexpr double kMaxOutside = 0.6;
// Wall points more than this above the roof along an edge belong to a taller
// neighbour's wall behind it (a parapet rises less).
constexpr double kAboveRoof = 0.5;
// Vertices closer than this are one vertex (validators snap at a millimetre);
// the plan rings, the shell and the wall profiles all weld at it.
constexpr double kWeldTol = 1e-3;  // m

struct EdgeInfo {
  Vec2 a, b;
  double overhang = 0;
  double sigma = 0.3;   // of the wall position, m
  int support = 0;
  bool party = false;
  WallEvidence evidence = WallEvidence::Default;
};

struct Piece {
  int region = 0;
  bool inside = true;   // inside the walls (part of the solid) or hanging
  Polygon2 plan;
};

// Median of values weighted by length: a building's overhang is what most of
// its eave length shows, not what most of its (often short) wall pieces show.
struct Weighted {
  double value, weight;
};
double weighted_median(std::vector<Weighted> v) {
  std::sort(v.begin(), v.end(), [](const Weighted& a, const Weighted& b) { return a.value < b.value; });
  double total = 0, run = 0;
  for (const auto& w : v) total += w.weight;
  for (const auto& w : v)
    if ((run += w.weight) >= 0.5 * total) return w.value;
  return v.back().value;
}

// The building's overhang from its seen walls: the length-weighted mean of
// those within kOverhangInlier of the weighted median. An edge's position is
// known to within σ² ∝ 1/length, so weighting by length is the least-variance
// estimate (the median alone throws a third of that information away); the
// median's window keeps flush jogs and step walls (overhang 0) out of it.
constexpr double kOverhangInlier = 0.1;  // m
double typical_overhang(const std::vector<Weighted>& measured) {
  double median = weighted_median(measured), sum = 0, weight = 0;
  for (const auto& m : measured)
    if (std::abs(m.value - median) <= kOverhangInlier) sum += m.value * m.weight, weight += m.weight;
  return sum / weight;  // the median itself is always within the window
}

// Facades parallel to each other overhang alike: on a pitched roof the eaves
// along the ridge share an overhang, and so do the verges across it, but the
// two often differ (a gable wall flush with the verge, a deep eave over the
// street). Where the seen walls parallel to a wall, a facade's length of them
// (a porch's flush sides are no facade), show an overhang clearly apart from
// the building's (more than a measurement's scatter), an unseen wall takes
// that facade's overhang, and a seen one is no misread for matching it.
constexpr double kParallelCos = 0.94;  // within 20 degrees
constexpr double kMinFacade = 3.0;     // m of seen wall
constexpr double kFacadeDiffers = 0.3; // m
struct SeenWall {
  size_t edge;        // index into the outline's edges
  Vec2 dir;
  Weighted overhang;  // weighted by length
};
double facade_overhang(const std::vector<SeenWall>& seen, const Vec2& dir, double building) {
  std::vector<Weighted> parallel;
  double length = 0;
  for (const auto& w : seen)
    if (std::abs(w.dir.dot(dir)) >= kParallelCos) parallel.push_back(w.overhang), length += w.overhang.weight;
  if (length < kMinFacade) return building;
  const double facade = typical_overhang(parallel);
  return std::abs(facade - building) > kFacadeDiffers ? facade : building;
}

// Roof height at p from the region over it (NaN where no region is).
double roof_z(const std::vector<RoofRegion>& roof, const Vec2& p) {
  for (const auto& r : roof)
    if (poly::covers(r.plan, p)) return r.plane.z_at(p.x(), p.y());
  return kNaN;
}

// Whether a short edge's line runs on into the roof as a step between levels
// (the gable of a higher part beside a lower annex). The step wall stands
// right under the step, so an unseen wall under such an edge is that same wall
// carried on: no overhang, where the building's typical one would cut a notch
// of that depth into the footprint. A longer edge is a wall of its own.
constexpr double kStepHeight = 0.5;  // m between the levels beside the line
constexpr double kStepJog = 2.0;     // m, longest edge taken for a continuation
bool continues_step(const EdgeInfo& e, const std::vector<RoofRegion>& roof) {
  if ((e.b - e.a).norm() > kStepJog) return false;
  const Vec2 d = (e.b - e.a).normalized(), n = outward(d);
  for (const auto& [end, sign] : {std::pair{e.a, -1.0}, std::pair{e.b, 1.0}})
    for (double t : {0.3, 0.6, 1.0}) {
      const Vec2 p = end + sign * t * d;
      const double z1 = roof_z(roof, p - 0.1 * n), z2 = roof_z(roof, p + 0.1 * n);
      if (std::abs(z1 - z2) > kStepHeight) return true;  // false while either is NaN
    }
  return false;
}

// Highest point of the roof over the band where this edge's wall may stand
// (+inf where no roof region covers it): wall points above it plus kAboveRoof
// are not this edge's wall.
double wall_top(const EdgeInfo& e, const std::vector<RoofRegion>& roof) {
  const Vec2 in = -outward((e.b - e.a).normalized());
  double top = -INFINITY;
  for (double t : {0.05, 0.5, 0.95})
    for (double depth : {0.2, kMaxOverhang}) {
      const double z = roof_z(roof, e.a + t * (e.b - e.a) + depth * in);
      if (std::isfinite(z)) top = std::max(top, z);
    }
  return std::isfinite(top) ? top + kAboveRoof : INFINITY;
}

// The wall seen under edge e, between 0.3 m above the terrain and wall_top.
WallFit fit_edge_wall(const EnvelopeInput& in, const EdgeInfo& e, bool beyond_ends = false) {
  const Vec2 mid = 0.5 * (e.a + e.b);
  const double tz = in.terrain(mid.x(), mid.y());
  return fit_wall(in.wall_points, e.a, e.b, std::isnan(tz) ? -1e9 : tz + 0.3, wall_top(e, in.roof), beyond_ends);
}

Vec2 direction(const EdgeInfo& e) { return (e.b - e.a).normalized(); }

// The wall under edge e: a wall the outline was grown onto, where e lies on
// its line (flush: offset 0), else the one fit_edge_wall finds. Fitting again
// after growing could pick another peak of a thick wall's points.
WallFit wall_on_outline(const EnvelopeInput& in, const EdgeInfo& e) {
  const Vec2 mid = 0.5 * (e.a + e.b);
  for (const auto& w : in.walls_on_outline) {
    const Vec2 d = (w.b - w.a).normalized();
    const double t = d.dot(mid - w.a);
    if (std::abs(d.dot(direction(e))) > 0.999 && std::abs(outward(d).dot(mid - w.a)) < 0.01 && t > 0 &&
        t < (w.b - w.a).norm()) {
      WallFit flush = w.fit;
      flush.offset = 0;
      return flush;
    }
  }
  return fit_edge_wall(in, e);
}

std::vector<EdgeInfo> measure_edges(const EnvelopeInput& in) {
  const Ring2& ring = in.outline.outer;
  std::vector<EdgeInfo> edges(ring.size());
  std::vector<SeenWall> seen;
  for (size_t i = 0; i < ring.size(); ++i) {
    EdgeInfo& e = edges[i];
    e.a = ring[i];
    e.b = ring[(i + 1) % ring.size()];
    e.party = i < in.party_edge.size() && in.party_edge[i];
    if (e.party) {  // on the parcel boundary, shared with the neighbour
      e.evidence = WallEvidence::ParcelBoundary;
      e.sigma = 0.05;
      continue;
    }
    const WallFit fit = wall_on_outline(in, e);
    if (fit.found && -fit.offset < kMaxOverhang) {
      e.overhang = std::max(0.0, -fit.offset);
      e.evidence = WallEvidence::Measured;
      e.support = fit.support;
      // A wall seen outside the outline stays under the roof at the outline:
      // its distance to the points it stands for is part of its error.
      e.sigma = 0.02 + fit.rms / std::sqrt(double(fit.support)) + std::max(0.0, fit.offset);
      seen.push_back({i, direction(e), {e.overhang, (e.b - e.a).norm()}});
    }
  }
  if (seen.empty()) {
    // No wall of this building seen (a row house between its neighbours): the
    // facade line may continue on the neighbours just past the edge's ends.
    for (auto& e : edges) {
      if (e.party) continue;
      const WallFit fit = fit_edge_wall(in, e, true);
      if (!fit.found) continue;
      e.overhang = std::max(0.0, -fit.offset);
      e.evidence = WallEvidence::Propagated;
      e.support = fit.support;
      e.sigma = 0.05 + fit.rms / std::sqrt(double(fit.support));
    }
  }
  double spread = 0.3;
  double typical = in.default_overhang;
  WallEvidence fill = WallEvidence::Default;
  std::vector<double> facade(edges.size(), typical);
  if (!seen.empty()) {
    std::vector<Weighted> measured;
    for (const auto& w : seen) measured.push_back(w.overhang);
    typical = typical_overhang(measured);
    for (size_t i = 0; i < edges.size(); ++i) facade[i] = facade_overhang(seen, direction(edges[i]), typical);
    for (size_t i = 0; i < edges.size(); ++i) {
      EdgeInfo& e = edges[i];
      if (e.evidence == WallEvidence::Measured && e.overhang - std::max(typical, facade[i]) > kOverhangOutlier) {
        e.evidence = WallEvidence::Default;  // re-filled below as propagated
        e.support = 0;
      }
    }
    std::vector<Weighted> dev;
    for (const auto& w : seen) dev.push_back({std::abs(w.overhang.value - facade[w.edge]), w.overhang.weight});
    spread = std::max(0.05, 1.4826 * weighted_median(dev));
    fill = WallEvidence::Propagated;
  }
  for (size_t i = 0; i < edges.size(); ++i) {
    EdgeInfo& e = edges[i];
    if (!e.party && e.evidence != WallEvidence::Measured && e.support == 0) {
      const bool step = continues_step(e, in.roof);
      e.overhang = step ? 0.0 : facade[i];
      e.evidence = step ? WallEvidence::Propagated : fill;
      e.sigma = step ? 0.05 : spread;
    }
  }
  if (log::enabled(log::Level::Debug))
    for (auto& e : edges)
      log::debug(log::format("%s edge len %.2f ev %s overhang %.3f support %d", in.building_id.c_str(),
                             (e.b - e.a).norm(), to_string(e.evidence), e.overhang, e.support));
  return edges;
}

// The first vertex of r lying within the weld tolerance of an edge of r but
// not of that edge's ends, and the edge's start; nullopt when none does.
std::optional<std::pair<size_t, size_t>> vertex_on_edge(const Ring2& r) {
  const size_t n = r.size();
  for (size_t k = 0; k < n; ++k)
    for (size_t i = 0; i < n; ++i) {
      const size_t j = (i + 1) % n;
      if ((r[k] - r[i]).norm() < kWeldTol || (r[k] - r[j]).norm() < kWeldTol) continue;
      const Vec2 d = r[j] - r[i];
      const double t = std::clamp(d.dot(r[k] - r[i]) / std::max(d.squaredNorm(), 1e-18), 0.0, 1.0);
      if ((r[i] + t * d - r[k]).norm() < kWeldTol) return std::make_pair(k, i);
    }
  return std::nullopt;
}

// Whether the ring passes twice through one vertex (within the weld tolerance).
bool pinched(const Ring2& r) {
  for (size_t i = 0; i < r.size(); ++i)
    for (size_t j = i + 1; j < r.size(); ++j)
      if ((r[i] - r[j]).norm() < kWeldTol) return true;
  return false;
}

// Whether the ring comes back within the weld tolerance of a vertex after
// leaving it (a pinch between two lobes), or a vertex lies on an edge away
// from that edge's ends (a fold: a spike of no width). Welded and noded, such
// a ring passes twice through one vertex. A cluster of vertices within the
// tolerance (a micro zig-zag) is neither: it is one vertex.
bool touches_itself(const Ring2& r) {
  const size_t n = r.size();
  auto leaves = [&](size_t from, size_t to, const Vec2& c) {  // some vertex strictly between is away from c
    for (size_t k = (from + 1) % n; k != to; k = (k + 1) % n)
      if ((r[k] - c).norm() >= kWeldTol) return true;
    return false;
  };
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 1; j < n; ++j)
      if ((r[i] - r[j]).norm() < kWeldTol && leaves(i, j, r[i]) && leaves(j, i, r[i])) return true;
  return vertex_on_edge(r).has_value();
}

// A ring passing twice through one vertex becomes two simple rings; holes go
// to the part holding them. Vertices closer than `tolerance` count as one.
std::vector<Polygon2> split_pinched(const Polygon2& p, double tolerance) {
  std::vector<Ring2> todo{p.outer}, done;
  while (!todo.empty()) {
    Ring2 r = todo.back();
    todo.pop_back();
    bool split = false;
    for (size_t i = 0; i < r.size() && !split; ++i)
      for (size_t j = i + 1; j < r.size() && !split; ++j)
        if ((r[i] - r[j]).norm() < tolerance) {
          Ring2 a(r.begin() + long(i), r.begin() + long(j));
          Ring2 b(r.begin() + long(j), r.end());
          b.insert(b.end(), r.begin(), r.begin() + long(i));
          todo.push_back(a);
          todo.push_back(b);
          split = true;
        }
    if (!split && r.size() >= 3 && std::abs(signed_area(r)) > 1e-6) done.push_back(r);
  }
  std::vector<Polygon2> out;
  for (auto& r : done) out.push_back({r, {}});
  for (const auto& h : p.holes)
    for (auto& o : out)
      if (poly::covers({Polygon2{o.outer, {}}}, h.front()) ||
          poly::covers({Polygon2{o.outer, {}}}, 0.5 * (h[0] + h[1]))) {
        o.holes.push_back(h);
        break;
      }
  return out;
}

// Parts whose ring comes within the weld tolerance of itself split into
// simple parts there: at a pinch (two lobes of a footprint where the inset
// outline narrows to nothing) and at a fold (a spike of no width: its vertex
// is put into the edge it lies on first). Welded, such a ring would pass
// twice through one vertex and no solid closes round it.
MultiPolygon2 separate_pinched(const MultiPolygon2& parts) {
  MultiPolygon2 out;
  for (Polygon2 part : parts) {
    if (!touches_itself(part.outer)) {
      out.push_back(std::move(part));
      continue;
    }
    Ring2& r = part.outer;
    for (size_t guard = r.size(); guard > 0; --guard) {  // the vertex into the edge it touches
      const auto touch = vertex_on_edge(r);
      if (!touch) break;
      const Vec2 v = r[touch->first];  // a copy: the insert may move r
      r.insert(r.begin() + long(touch->second) + 1, v);
    }
    for (Polygon2& lobe : split_pinched(part, kWeldTol)) out.push_back(std::move(lobe));
  }
  return out;
}

// Consecutive edges closer to one line than this (sin 3 degrees) whose
// overhangs differ by more than kMinStepM do not meet in a corner (their
// moved lines cross far off, or nowhere): the footprint steps between them.
// A smaller difference is no change of wall kind, and a step of millimetres
// would keep the footprint from being regularised.
constexpr double kInLineSin = 0.052;
constexpr double kMinStepM = 0.05;

// The footprint without edges shorter than kSpeckM: an edge of a millimetre
// or two (where a moved line crosses the roof outline next to one of its
// vertices) puts roof corners closer than anything can be welded, with a
// triangle a few millimetres wide between them that their heights tilt. Of
// its two ends the one whose removal moves the footprint least goes.
constexpr double kSpeckM = 0.005;
Polygon2 without_specks(const Polygon2& fp) {
  Ring2 r = fp.outer;
  auto bend = [&](size_t k) {  // twice the area dropping vertex k takes or gives
    const size_t n = r.size();
    const Vec2 u = r[k] - r[(k + n - 1) % n], v = r[(k + 1) % n] - r[k];
    return std::abs(u.x() * v.y() - u.y() * v.x());
  };
  for (size_t i = 0; i < r.size() && r.size() > 3;) {
    const size_t j = (i + 1) % r.size();
    if ((r[j] - r[i]).norm() >= kSpeckM) {
      ++i;
      continue;
    }
    r.erase(r.begin() + long(bend(i) <= bend(j) ? i : j));
    i = 0;
  }
  Polygon2 out{r, {}};
  return r.size() >= 3 && poly::is_valid({out}) ? out : fp;
}

// Each outline edge moved inward by its overhang; corners where the moved lines meet.
Polygon2 footprint_from_edges(const std::vector<EdgeInfo>& edges, const EnvelopeInput& in,
                              FootprintApart* apart) {
  Ring2 ring;
  bool stepped = false;
  size_t n = edges.size();
  for (size_t i = 0; i < n; ++i) {
    const EdgeInfo& p = edges[(i + n - 1) % n];
    const EdgeInfo& c = edges[i];
    Vec2 dp = (p.b - p.a).normalized(), dc = (c.b - c.a).normalized();
    Vec2 op = p.a - outward(dp) * p.overhang, oc = c.a - outward(dc) * c.overhang;
    const bool in_line = std::abs(dp.x() * dc.y() - dp.y() * dc.x()) < kInLineSin && dp.dot(dc) > 0;
    if (in_line && std::abs(p.overhang - c.overhang) > kMinStepM) {  // a party wall running on as a free wall
      ring.push_back(c.a - outward(dp) * p.overhang);  // the step: from p's moved line to c's
      ring.push_back(oc);
      stepped = true;
    } else {
      ring.push_back(intersect_lines(op, dp, oc, dc).value_or(oc));
    }
  }
  MultiPolygon2 valid = poly::drop_small(poly::make_valid({Polygon2{ring, {}}}), 0.5);
  valid = separate_pinched(poly::intersect(valid, {in.outline}));
  if (valid.empty()) valid = poly::buffer({in.outline}, -in.default_overhang);
  if (valid.empty()) throw std::runtime_error("roof outline too small for a footprint");
  Polygon2 best = poly::largest(valid);
  best.holes.clear();
  if (apart) {
    for (const Polygon2& part : valid)
      if (area(part) >= kMinFootprintPart) apart->parts.push_back(part);
    std::sort(apart->parts.begin(), apart->parts.end(),
              [](const Polygon2& a, const Polygon2& b) { return area(a) > area(b); });
    for (const EdgeInfo& e : edges) apart->overhang = std::max(apart->overhang, e.overhang);
  }
  // Regularising would merge the lines of a step (0.3 m apart or less) and
  // give the whole side one overhang and one kind of wall; a stepped ring
  // that pinches (passes twice through a vertex) is regularised all the same.
  if (stepped && !pinched(best.outer)) return best;
  // Regularising may push a corner past the roof outline; the walls must stay
  // under the roof, or the roof would not close the solid there.
  MultiPolygon2 under = separate_pinched(poly::intersect({regularize_polygon(best, 1.0)}, {in.outline}));
  if (under.empty()) return best;
  Polygon2 fp = poly::largest(under);
  fp.holes.clear();
  return fp;
}

double mean_terrain(const Polygon2& fp, const std::function<double(double, double)>& terrain) {
  Vec2 lo = fp.outer[0], hi = lo;
  for (const auto& p : fp.outer) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  double sum = 0;
  int n = 0;
  MultiPolygon2 mp{fp};
  for (double x = lo.x() + 0.25; x < hi.x(); x += 0.5)
    for (double y = lo.y() + 0.25; y < hi.y(); y += 0.5) {
      if (!poly::covers(mp, {x, y})) continue;
      double z = terrain(x, y);
      if (!std::isnan(z)) sum += z, ++n;
    }
  for (const auto& p : fp.outer) {
    double z = terrain(p.x(), p.y());
    if (!std::isnan(z)) sum += z, ++n;
  }
  if (n == 0) throw std::runtime_error("the terrain model does not cover the building");
  return sum / n;
}

// z of every (piece, vertex): its plane, welded with the other pieces' heights
// at the same vertex when they agree within 2 mm (numerically the same line).
class Heights {
 public:
  void add(const Vec2& v, double z) { at_[key(v)].push_back(z); }
  double get(const Vec2& v, double z) const {
    auto it = at_.find(key(v));
    if (it == at_.end()) return z;
    const bool all = at_mean_.count(key(v)) > 0;
    double sum = 0;
    int n = 0;
    for (double o : it->second)
      if (all || std::abs(o - z) < 0.002) sum += o, ++n;
    return n ? sum / n : z;
  }
  // Every piece at v takes the mean of their heights, if they lie within 1 cm.
  void meet_at_mean(const Vec2& v) {
    auto it = at_.find(key(v));
    if (it == at_.end()) return;
    const auto [lo, hi] = std::minmax_element(it->second.begin(), it->second.end());
    if (*hi - *lo < 0.01) at_mean_.insert(key(v));
  }

 private:
  static std::pair<double, double> key(const Vec2& v) { return {v.x(), v.y()}; }
  std::map<std::pair<double, double>, std::vector<double>> at_;
  std::set<std::pair<double, double>> at_mean_;
};

Ring3 lift(const Ring2& r, const Plane& plane, const Heights& h) {
  Ring3 out;
  for (const auto& v : r) out.emplace_back(v.x(), v.y(), h.get(v, plane.z_at(v.x(), v.y())));
  return out;
}

// A roof piece on its plane, holes included.
Face lift(const Piece& p, const Plane& plane, const Heights& h) {
  Face f{lift(p.plan.outer, plane, h), {}};
  for (const auto& hole : p.plan.holes) f.holes.push_back(lift(hole, plane, h));
  return f;
}

Ring3 flat(const Ring2& r, double z, bool downward) {
  Ring3 out;
  for (const auto& v : r) out.emplace_back(v.x(), v.y(), z);
  if (downward) std::reverse(out.begin(), out.end());
  return out;
}

// A roof piece's edge over a footprint edge: from t0 to t1 along it, at
// heights z0 and z1, its ends at0 and at1 in plan (within the weld tolerance
// of the edge, not always on it); `along`: the piece's edge runs along the
// footprint edge, not across its end (a few millimetres of the next edge).
struct ProfileSegment {
  double t0, z0, t1, z1;
  Vec2 at0, at1;
  bool along;
};

constexpr double kAlongSlope = 0.1;  // a piece's edge within 6 degrees of the footprint edge runs along it

// The roof underside along a footprint edge, from the inside pieces' edges on it.
std::vector<ProfileSegment> roof_profile(const Vec2& a, const Vec2& b,
                                         const std::vector<Face>& inside_faces) {
  Vec2 d = b - a;
  double len = d.norm();
  d /= len;
  Vec2 n = outward(d);
  std::vector<ProfileSegment> segs;
  for (const auto& f : inside_faces) {
    const Ring3& r = f.ring;
    for (size_t i = 0; i < r.size(); ++i) {
      const Vec3& p = r[i];
      const Vec3& q = r[(i + 1) % r.size()];
      Vec2 p2 = p.head<2>() - a, q2 = q.head<2>() - a;
      if (std::abs(n.dot(p2)) > 2 * kWeldTol || std::abs(n.dot(q2)) > 2 * kWeldTol) continue;  // welded ends may sit off the line
      double tp = d.dot(p2), tq = d.dot(q2);
      if (std::min(tp, tq) < -2 * kWeldTol || std::max(tp, tq) > len + 2 * kWeldTol) continue;
      if (std::abs(tp - tq) < 1e-7) continue;
      tp = std::clamp(tp, 0.0, len);  // welding may put an end past the corner, as it may off the line
      tq = std::clamp(tq, 0.0, len);
      if (std::abs(tp - tq) < 1e-7) continue;
      const bool along = std::abs(n.dot(q2 - p2)) < kAlongSlope * std::abs(tq - tp);
      if (tp < tq) segs.push_back({tp, p.z(), tq, q.z(), p.head<2>(), q.head<2>(), along});
      else segs.push_back({tq, q.z(), tp, p.z(), q.head<2>(), p.head<2>(), along});
    }
  }
  std::sort(segs.begin(), segs.end(), [](auto& x, auto& y) { return x.t0 > y.t0; });
  return segs;
}

Face wall_face(const Vec2& a, const Vec2& b, double ground_z,
               const std::vector<ProfileSegment>& profile) {
  // Breakpoints of the profile; on each interval the highest roof piece over it
  // is the underside the wall meets (overlaps of clipped pieces are numerical).
  std::vector<double> ts;
  for (const auto& s : profile) ts.push_back(s.t0), ts.push_back(s.t1);
  std::sort(ts.begin(), ts.end());
  // Breakpoints closer than the weld tolerance are one: a roof piece touching
  // the edge over less than a millimetre (a corner on a step line) would put a
  // spike of no width into the wall.
  ts.erase(std::unique(ts.begin(), ts.end(), [](double x, double y) { return y - x < kWeldTol; }),
           ts.end());
  auto z_on = [](const ProfileSegment& s, double t) {
    return s.z0 + (s.z1 - s.z0) * (t - s.t0) / (s.t1 - s.t0);
  };
  Vec2 d = (b - a).normalized();
  Face f;
  f.ring.emplace_back(a.x(), a.y(), ground_z);
  f.ring.emplace_back(b.x(), b.y(), ground_z);
  // The wall meets the roof at the corner of a piece running along the edge
  // where one ends there: a corner may sit a millimetre or two off the edge,
  // more than the weld joins. At the footprint's corners the walls meet each
  // other.
  const double len = (b - a).norm();
  auto push = [&](const ProfileSegment& s, double t) {
    Vec2 at = a + t * d;
    if (t < kWeldTol) at = a;
    else if (t > len - kWeldTol) at = b;
    else if (s.along && std::abs(t - s.t0) < kWeldTol) at = s.at0;
    else if (s.along && std::abs(t - s.t1) < kWeldTol) at = s.at1;
    // A roof below the terrain (bad data) must not fold the wall over itself.
    Vec3 v(at.x(), at.y(), std::max(z_on(s, t), ground_z + 0.01));
    if ((f.ring.back() - v).norm() > 1e-7) f.ring.push_back(v);
  };
  for (size_t k = ts.size(); k-- > 1;) {  // from b back to a
    double hi = ts[k], lo = ts[k - 1], mid = 0.5 * (hi + lo);
    const ProfileSegment* best = nullptr;
    for (const auto& s : profile)
      if (s.t0 <= mid && s.t1 >= mid && (!best || z_on(s, mid) > z_on(*best, mid))) best = &s;
    if (!best) continue;
    push(*best, hi);
    push(*best, lo);
  }
  if ((f.ring.back() - f.ring.front()).norm() < 1e-7) f.ring.pop_back();
  return f;
}

// An edge in plan by its exact end coordinates: pieces of one planar
// subdivision share edges exactly, so plain keys match across pieces.
using EdgeKey = std::pair<std::pair<double, double>, std::pair<double, double>>;

EdgeKey directed(const Vec2& a, const Vec2& b) { return {{a.x(), a.y()}, {b.x(), b.y()}}; }

EdgeKey undirected(const Vec2& a, const Vec2& b) {
  return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y()) ? directed(a, b) : directed(b, a);
}

// Vertical faces where two inside roof pieces meet at different heights,
// grouped by the roof region above them: one step wall element per roof plane,
// however many edge pieces (and lower neighbours) its foot is made of.
std::map<int, std::vector<Face>> step_walls(const std::vector<Face>& inside,
                                            const std::vector<int>& region_of) {
  // Every ring of every piece, holes included: an island piece meets the hole
  // of the piece around it along opposite edges.
  std::vector<const Ring3*> rings;
  std::vector<int> piece_of;
  for (size_t f = 0; f < inside.size(); ++f) {
    rings.push_back(&inside[f].ring);
    piece_of.push_back(int(f));
    for (const auto& h : inside[f].holes) rings.push_back(&h), piece_of.push_back(int(f));
  }
  auto key = [](const Vec3& p, const Vec3& q) { return directed(p.head<2>(), q.head<2>()); };
  std::map<EdgeKey, std::pair<int, int>> edge_at;  // (ring, vertex)
  for (size_t k = 0; k < rings.size(); ++k)
    for (size_t i = 0; i < rings[k]->size(); ++i)
      edge_at[key((*rings[k])[i], (*rings[k])[(i + 1) % rings[k]->size()])] = {int(k), int(i)};
  std::map<int, std::vector<Face>> out;
  for (size_t k = 0; k < rings.size(); ++k) {
    const Ring3& r = *rings[k];
    for (size_t i = 0; i < r.size(); ++i) {
      const Vec3& p = r[i];
      const Vec3& q = r[(i + 1) % r.size()];
      auto it = edge_at.find(key(q, p));
      if (it == edge_at.end() || piece_of[it->second.first] == piece_of[k]) continue;
      const Ring3& o = *rings[it->second.first];
      const Vec3& oq = o[it->second.second];
      const Vec3& op = o[(it->second.second + 1) % o.size()];
      double dp = p.z() - op.z(), dq = q.z() - oq.z();
      if ((dp > 1e-6 && dq < -1e-6) || (dp < -1e-6 && dq > 1e-6)) {
        // The two roofs cross along the edge (an outer ring or a hole's): each
        // walls the part where it is the higher, a triangle up to the crossing
        // point, which lies on both roofs; noding the shell puts it into their edges.
        const Vec3 c = p + dp / (dp - dq) * (q - p);
        out[region_of[piece_of[k]]].push_back(dp > 0 ? Face{{op, c, p}, {}} : Face{{c, oq, q}, {}});
        continue;
      }
      if (dp < -1e-6 || dq < -1e-6 || (dp < 1e-6 && dq < 1e-6)) continue;  // we are not the higher side
      Face w;
      w.ring.push_back(op);
      w.ring.push_back(oq);
      if (dq > 1e-6) w.ring.push_back(q);
      if (dp > 1e-6) w.ring.push_back(p);
      if (w.ring.size() >= 3) out[region_of[piece_of[k]]].push_back(std::move(w));
    }
  }
  return out;
}

// Planes that miss one junction by more than the 2 mm weld (a cross gable's
// wing ridge 3 mm above the main ridge it runs into, five faces round one
// vertex) leave a step wall between each high and low neighbour there, three
// or more on one vertical edge, which no solid can hold. The pieces at such a
// vertex meet at the mean of their heights, each a few millimetres off its
// plane at that one corner. (Four regions round one vertex are split into two
// three-plane points before, exactly: split_four_plane_vertices.)
void meet_at_step_fans(Heights& heights, const std::vector<Piece>& pieces, const std::vector<RoofRegion>& roof) {
  std::vector<Face> inside;
  for (const auto& p : pieces)
    if (p.inside) inside.push_back(lift(p, roof[p.region].plane, heights));
  std::map<std::pair<double, double>, int> vertical_edges;
  for (const auto& [above, faces] : step_walls(inside, std::vector<int>(inside.size(), 0)))
    for (const Face& f : faces)
      for (size_t i = 0; i < f.ring.size(); ++i) {
        const Vec3& a = f.ring[i];
        if (a.head<2>() == f.ring[(i + 1) % f.ring.size()].head<2>()) ++vertical_edges[{a.x(), a.y()}];
      }
  for (const auto& [xy, n] : vertical_edges)
    if (n >= 4) heights.meet_at_mean(Vec2(xy.first, xy.second));
}

double perimeter(const Ring2& r) {
  double p = 0;
  for (size_t i = 0; i < r.size(); ++i) p += (r[(i + 1) % r.size()] - r[i]).norm();
  return p;
}

Element make_element(ElementType type, std::vector<Face> faces) {
  Element e;
  e.type = type;
  e.faces = std::move(faces);
  for (const auto& f : e.faces) {
    e.area += area(f);
    e.plan_area += plan_area(f);
  }
  if (type == ElementType::OuterCeiling) e.area = e.plan_area;
  return e;
}

// Nearest distance between two elements' vertices.
double vertex_gap(const Element& a, const Element& b) {
  double best = 1e18;
  for (const auto& fa : a.faces)
    for (const auto& p : fa.ring)
      for (const auto& fb : b.faces)
        for (const auto& q : fb.ring) best = std::min(best, (p - q).norm());
  return best;
}

// A step wall of a few square centimetres (two roof planes meeting millimetres
// apart near a junction) is no wall anyone could point at or cost: its faces
// stay in the shell but join the nearest wall element. The other step walls
// are appended to `elements` after the facades.
constexpr double kMinStepWallArea = 0.01;  // m^2
void fold_sliver_steps(std::vector<Element>& steps, std::vector<Element>& elements) {
  for (auto& e : steps)
    if (e.area >= kMinStepWallArea) elements.push_back(std::move(e));
  for (auto& e : steps) {
    if (e.area >= kMinStepWallArea) continue;  // listed above
    Element* host = nullptr;
    double gap = 1e18;
    for (auto& w : elements) {
      if (w.type != ElementType::Wall && w.type != ElementType::PartyWall) continue;
      const double d = vertex_gap(e, w);
      if (d < gap) gap = d, host = &w;
    }
    if (!host) {  // no other wall: keep it as it is
      elements.push_back(std::move(e));
      continue;
    }
    host->faces.insert(host->faces.end(), e.faces.begin(), e.faces.end());
    host->area += e.area;
    host->plan_area += e.plan_area;
    host->sigma_area = std::hypot(host->sigma_area, e.sigma_area);
  }
}

// Compass direction (degrees from north, clockwise) a face's normal points to.
double azimuth_of(const Face& f) {
  Vec3 n = unit_normal(f);
  return std::fmod(std::atan2(n.x(), n.y()) * 180 / M_PI + 360.0, 360.0);
}

const Face& widest_face(const Element& e) {
  return *std::max_element(e.faces.begin(), e.faces.end(),
                           [](const Face& x, const Face& y) { return area(x) < area(y); });
}

// Footprint edge -> outline edge it came from (parallel and nearest).
const EdgeInfo& source_edge(const std::vector<EdgeInfo>& edges, const Vec2& a, const Vec2& b) {
  Vec2 d = (b - a).normalized(), mid = 0.5 * (a + b);
  const EdgeInfo* best = &edges[0];
  double best_score = 1e18;
  for (const auto& e : edges) {
    Vec2 ed = (e.b - e.a).normalized();
    Vec2 em = 0.5 * (e.a + e.b);
    double off = std::abs(outward(ed).dot(mid - e.a));
    double along = std::max(0.0, std::abs(ed.dot(mid - em)) - 0.5 * (e.b - e.a).norm());
    double score = off + along + (ed.dot(d) < 0.98 ? 100.0 : 0.0);
    if (score < best_score) best_score = score, best = &e;
  }
  return *best;
}

// Vertices closer than tol become one (the first seen), and rings lose the
// consecutive duplicates that leaves: validators treat < 1 mm as the same point.
void weld_faces(std::vector<Face>& shell, double tol, std::vector<Vec3>& seen, bool drop_degenerate) {
  auto clean = [&](Ring3& r) {
    for (auto& v : r) weld_vertex(v, seen, tol);
    Ring3 out;
    for (const auto& v : r)
      if (out.empty() || (v - out.back()).norm() > 0) out.push_back(v);
    while (out.size() > 1 && out.front() == out.back()) out.pop_back();
    r = out;
  };
  for (auto& f : shell) {
    clean(f.ring);
    for (auto& h : f.holes) clean(h);
  }
  if (drop_degenerate)
    shell.erase(std::remove_if(shell.begin(), shell.end(),
                               [](const Face& f) { return f.ring.size() < 3 || area(f) < 1e-6; }),
                shell.end());
}

void set_height(Face& f, double z) {
  for (auto& v : f.ring) v.z() = z;
  for (auto& h : f.holes)
    for (auto& v : h) v.z() = z;
}

std::vector<Vec3> shell_vertices(const std::vector<Face>& shell) {
  std::vector<Vec3> verts;
  for (const auto& f : shell) {
    verts.insert(verts.end(), f.ring.begin(), f.ring.end());
    for (const auto& h : f.holes) verts.insert(verts.end(), h.begin(), h.end());
  }
  return verts;
}

// Inserts into every shell edge the shell vertices lying on it (a wall corner
// that meets a step between roof levels, a T-junction left by clipping), so each
// edge is shared by exactly two faces.
void node_faces(std::vector<Face>& shell, const std::vector<Vec3>& verts, double tol) {
  for (auto& f : shell) {
    f.ring = insert_on_edges(f.ring, verts, tol);
    for (auto& h : f.holes) h = insert_on_edges(h, verts, tol);
  }
}

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

// Parts of a region narrower than twice this are partition artefacts (spikes
// along a neighbour, slivers at the footprint), not roof a scan can support.
constexpr double kThin = 0.05;
// A separate fragment of a region smaller than this, beside a larger part of
// the same region, is an artefact too (label-grid teeth touching at corners).
constexpr double kFragment = 0.5;

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

// Faces marked merge take the region of the neighbour they share most boundary
// with, a neighbour on the same side of the walls first; a face never changes
// side (the solid's top must cover the footprint exactly). Repeated so chains
// of slivers resolve.
void merge_marked(std::vector<FaceOwner>& owner, const std::vector<std::map<int, double>>& shared) {
  for (bool changed = true; changed;) {
    changed = false;
    for (size_t f = 0; f < owner.size(); ++f) {
      if (!owner[f].merge) continue;
      int best = -1;
      double best_score = 0;
      for (const auto& [g, len] : shared[f]) {
        double score = len + (owner[g].inside == owner[f].inside ? 1e6 : 0.0);
        if (!owner[g].merge && owner[g].region >= 0 && score > best_score) best = g, best_score = score;
      }
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
    for (auto& t : poly::drop_small(poly::subtract(plans.back(), opened), 1e-4)) thin.push_back(t);
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

  constexpr double kSliver = 1e-3, kGap = 0.05;  // m^2
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
  merge_marked(owner, shared);
  for (int round = 0; round < 3 && mark_fragments(faces, owner, shared); ++round)
    merge_marked(owner, shared);

  std::map<std::pair<int, bool>, MultiPolygon2> groups;
  for (size_t f = 0; f < faces.size(); ++f)
    if (owner[f].region >= 0) groups[{owner[f].region, owner[f].inside}].push_back(faces[f]);
  std::vector<Piece> pieces;
  for (auto& [key, group] : groups)
    for (auto& p : poly::unite_all({group})) pieces.push_back({key.first, key.second, p});
  return pieces;
}

// Developer aid: prints shell edges used by one face only (C3D_DEBUG=1).
void debug_open_edges(const Building& b) {
  auto key = [](const Vec3& p) {
    return std::make_tuple(std::llround(p.x() * 1e4), std::llround(p.y() * 1e4), std::llround(p.z() * 1e4));
  };
  std::map<std::pair<decltype(key(Vec3())), decltype(key(Vec3()))>, int> use;
  auto count = [&](const Ring3& r) {
    for (size_t i = 0; i < r.size(); ++i) {
      auto a = key(r[i]), c = key(r[(i + 1) % r.size()]);
      use[{std::min(a, c), std::max(a, c)}]++;
    }
  };
  for (const auto& f : b.solid) {
    count(f.ring);
    for (const auto& h : f.holes) count(h);
  }
  for (auto& [e, n] : use)
    if (n != 2)
      log::debug(log::format("%s open edge x%d (%.3f %.3f %.3f)-(%.3f %.3f %.3f)", b.id.c_str(), n,
                             std::get<0>(e.first) * 1e-4, std::get<1>(e.first) * 1e-4, std::get<2>(e.first) * 1e-4,
                             std::get<0>(e.second) * 1e-4, std::get<1>(e.second) * 1e-4, std::get<2>(e.second) * 1e-4));
}

// The wall at offset `centre` (points within 0.08 m of it), or found=false
// when too few points show it or they cover too little of the edge.
WallFit wall_at(const std::vector<std::pair<double, double>>& st, double centre, double len,
                bool beyond_ends) {
  WallFit fit;
  double sum = 0, sum2 = 0;
  int count = 0;
  std::vector<bool> covered(size_t(len / 0.5) + 1, false);
  for (auto& [s, t] : st)
    if (std::abs(s - centre) < 0.08) {
      sum += s;
      ++count;
      if (!beyond_ends) covered[size_t(t / 0.5)] = true;
    }
  if (count < 25) return fit;
  double mean = sum / count;
  for (auto& [s, t] : st)
    if (std::abs(s - centre) < 0.08) sum2 += (s - mean) * (s - mean);
  double coverage = double(std::count(covered.begin(), covered.end(), true)) / covered.size();
  if (!beyond_ends && coverage < 0.3) return fit;
  fit.found = true;
  fit.offset = mean;
  fit.support = count;
  fit.rms = std::sqrt(sum2 / count);
  return fit;
}

}  // namespace

Face wall_under(const Vec2& a, const Vec2& b, double ground_z, const std::vector<Face>& inside_pieces) {
  const auto profile = roof_profile(a, b, inside_pieces);
  return profile.empty() ? Face{} : wall_face(a, b, ground_z, profile);
}

WallFit fit_wall(const std::vector<Vec3>& pts, const Vec2& a, const Vec2& b, double min_z, double max_z,
                 bool beyond_ends) {
  Vec2 d = b - a;
  double len = d.norm();
  if (len < 0.8) return {};
  d /= len;
  Vec2 n = outward(d);
  const double lo = -kMaxOverhang, hi = kMaxOutside, bin = 0.04;
  std::vector<int> hist(int((hi - lo) / bin) + 1, 0);
  std::vector<std::pair<double, double>> st;  // (s, t)
  for (const auto& p : pts) {
    if (p.z() < min_z || p.z() > max_z) continue;
    Vec2 q = p.head<2>() - a;
    double t = d.dot(q), s = n.dot(q);
    bool along = beyond_ends ? ((t < 0 && t > -kMaxOverhang) || (t > len && t < len + kMaxOverhang))
                             : (t >= 0.1 * len && t <= 0.9 * len);
    if (!along || s < lo || s > hi) continue;
    ++hist[int((s - lo) / bin)];
    st.emplace_back(s, t);
  }
  if (st.size() < 25) return {};
  // Peaks of the offset histogram (3 bins wide), most points first: a short
  // bright patch (a pole, a gate) must not hide the wall behind it.
  const size_t bins = hist.size();
  std::vector<int> smooth(bins);
  for (size_t i = 0; i < bins; ++i)
    smooth[i] = hist[i] + (i > 0 ? hist[i - 1] : 0) + (i + 1 < bins ? hist[i + 1] : 0);
  std::vector<std::pair<int, int>> peaks;  // (count, bin)
  for (size_t i = 0; i < bins; ++i)
    if ((i == 0 || smooth[i] > smooth[i - 1]) && (i + 1 == bins || smooth[i] >= smooth[i + 1]))
      peaks.emplace_back(smooth[i], int(i));
  std::sort(peaks.rbegin(), peaks.rend());
  for (const auto& [count, i] : peaks) {
    const WallFit fit = wall_at(st, lo + (i + 0.5) * bin, len, beyond_ends);
    if (fit.found) return fit;
  }
  return {};
}

// A wall this little outside the outline is within the outline's own error
// (a hull edge is placed to about a centimetre, a wall fit to millimetres).
constexpr double kMinOutside = 0.05;

GrownOutline grow_to_walls_outside(const EnvelopeInput& in, const MultiPolygon2& room) {
  const Ring2& ring = in.outline.outer;
  const size_t n = ring.size();
  std::vector<WallFit> fits(n);  // the walls standing outside their edges
  for (size_t i = 0; i < n; ++i) {
    if (i < in.party_edge.size() && in.party_edge[i]) continue;
    EdgeInfo e;
    e.a = ring[i], e.b = ring[(i + 1) % n];
    const WallFit fit = fit_edge_wall(in, e);
    if (fit.found && fit.offset > kMinOutside) fits[i] = fit;
  }
  auto out = [&](size_t i) { return fits[i % n].found ? fits[i % n].offset : 0.0; };
  GrownOutline g{in.outline, {}};
  MultiPolygon2 grown{in.outline};
  for (size_t i = 0; i < n; ++i) {
    if (!fits[i].found) continue;
    const Vec2 a = ring[i], b = ring[(i + 1) % n], d = (b - a).normalized(), o = outward(d) * out(i);
    // Run on past each end by the next edge's growth, so that two grown edges
    // meet in a corner rather than leave a notch (at a reflex corner the run
    // on lies inside the outline already).
    const Vec2 a0 = a - d * out(i + n - 1), b0 = b + d * out(i + 1);
    const MultiPolygon2 strip = poly::intersect({Polygon2{{a0, b0, b0 + o, a0 + o}, {}}}, room);
    if (area(strip) < 0.05) continue;  // no land to grow on
    grown = poly::unite(grown, strip);
    g.walls.push_back({a0 + o, b0 + o, fits[i]});
  }
  Polygon2 best = poly::largest(poly::simplify(grown, 0.005));
  best.holes.clear();
  if (area(best) > area(in.outline) + 0.05)
    g.outline = best;
  else
    g.walls.clear();
  return g;
}

Building build_building(const EnvelopeInput& in, FootprintApart* apart) {
  Building b;
  b.id = in.building_id;
  std::vector<EdgeInfo> edges = measure_edges(in);
  Polygon2 fp = without_specks(footprint_from_edges(edges, in, apart));
  b.terrain_z = mean_terrain(fp, in.terrain);

  std::vector<Piece> pieces = roof_pieces(in.roof, fp);
  Polygon2 fp_copy = fp;
  std::vector<Ring2*> rings{&fp_copy.outer};
  for (auto& p : pieces) {
    rings.push_back(&p.plan.outer);
    for (auto& h : p.plan.holes) rings.push_back(&h);
  }
  node_rings(rings, kWeldTol);
  std::vector<Piece> simple;
  for (const auto& p : pieces)
    for (auto& part : split_pinched(p.plan, 1e-9))  // an overhang frame's hole touching its outline
      simple.push_back({p.region, p.inside, part});
  pieces = std::move(simple);

  Heights heights;
  for (const auto& p : pieces) {
    const Plane& pl = in.roof[p.region].plane;
    for (const auto& v : p.plan.outer) heights.add(v, pl.z_at(v.x(), v.y()));
    for (const auto& h : p.plan.holes)
      for (const auto& v : h) heights.add(v, pl.z_at(v.x(), v.y()));
  }
  meet_at_step_fans(heights, pieces, in.roof);
  std::vector<std::vector<Face>> roof_faces(in.roof.size());
  std::vector<Face> inside, soffits;
  std::vector<int> inside_region;
  for (const auto& p : pieces) {
    const Face f = lift(p, in.roof[p.region].plane, heights);
    roof_faces[p.region].push_back(f);
    if (p.inside) {
      inside.push_back(f);
      inside_region.push_back(p.region);
    } else {
      double zmin = 1e18;
      for (const auto& v : f.ring) zmin = std::min(zmin, v.z());
      Face s{flat(p.plan.outer, zmin, true), {}};
      for (const auto& h : p.plan.holes) s.holes.push_back(flat(h, zmin, true));
      soffits.push_back(std::move(s));
    }
  }

  // Roof elements: one per plane, overhang included.
  for (size_t r = 0; r < in.roof.size(); ++r) {
    if (roof_faces[r].empty()) continue;
    Element e = make_element(ElementType::Roof, roof_faces[r]);
    const Plane& pl = in.roof[r].plane;
    const PlaneFit& fit = in.fits[r];
    e.slope_deg = pl.slope_deg();
    e.azimuth_deg = pl.azimuth_deg();
    e.support_points = fit.inliers;
    e.rmse = fit.rmse;
    double per = 0;
    for (const auto& part : in.roof[r].plan) per += perimeter(part.outer);
    double tilt = e.area * std::tan(pl.slope_deg() * M_PI / 180) * fit.sigma_normal;
    double edge = 0.5 * per * 0.25 * in.spacing;
    e.sigma_area = std::sqrt(tilt * tilt + edge * edge);
    b.elements.push_back(std::move(e));
  }

  // Walls along the footprint, from the terrain up to the roof underside: one
  // element per outline edge they stand under (a notch in the footprint does
  // not split a facade into separate elements).
  std::vector<Face> solid;
  double sigma_ground2 = 0;
  std::vector<std::pair<const EdgeInfo*, std::vector<Face>>> facades;
  for (size_t i = 0; i < fp.outer.size(); ++i) {
    Vec2 a = fp.outer[i], c = fp.outer[(i + 1) % fp.outer.size()];
    Face f = wall_under(a, c, b.terrain_z, inside);
    if (f.ring.size() < 3) continue;
    const EdgeInfo* src = &source_edge(edges, a, c);
    sigma_ground2 += std::pow((c - a).norm() * src->sigma, 2);
    solid.push_back(f);
    if (facades.empty() || facades.back().first != src) facades.push_back({src, {}});
    facades.back().second.push_back(std::move(f));
  }
  if (facades.size() > 1 && facades.front().first == facades.back().first) {  // wraps round
    auto& last = facades.back().second;
    facades.front().second.insert(facades.front().second.begin(), last.begin(), last.end());
    facades.pop_back();
  }
  for (auto& [src, faces] : facades) {
    double len = 0;
    for (const auto& f : faces) len += (f.ring[1] - f.ring[0]).head<2>().norm();  // ground edge
    Element e = make_element(src->party ? ElementType::PartyWall : ElementType::Wall, std::move(faces));
    e.evidence = src->evidence;
    e.support_points = src->support;
    e.azimuth_deg = azimuth_of(widest_face(e));
    e.slope_deg = 90.0;
    double height = e.area / std::max(len, 1e-9);
    double s_top = 0.05, s_len = src->sigma;
    e.sigma_area = std::sqrt(std::pow(len * s_top, 2) + std::pow(height * s_len, 2));
    b.elements.push_back(std::move(e));
  }
  std::vector<Element> steps;
  for (auto& [above, faces] : step_walls(inside, inside_region)) {
    solid.insert(solid.end(), faces.begin(), faces.end());
    Element e = make_element(ElementType::Wall, std::move(faces));
    e.evidence = WallEvidence::RoofStep;
    e.slope_deg = 90.0;
    e.sigma_area = 0.05 * std::sqrt(e.area);
    e.azimuth_deg = azimuth_of(widest_face(e));
    steps.push_back(std::move(e));
  }
  fold_sliver_steps(steps, b.elements);

  Face ground{flat(fp.outer, b.terrain_z, true), {}};
  Element g = make_element(ElementType::Ground, {ground});
  g.sigma_area = std::sqrt(sigma_ground2);
  b.elements.push_back(g);
  solid.push_back(ground);
  solid.insert(solid.end(), inside.begin(), inside.end());

  if (!soffits.empty()) {
    Element oc = make_element(ElementType::OuterCeiling, soffits);
    double edge = perimeter(in.outline.outer) * 0.25 * in.spacing;
    oc.sigma_area = std::sqrt(sigma_ground2 + edge * edge);
    b.elements.push_back(std::move(oc));
  }
  // Weld and node the shell, then the element faces against the same vertices,
  // so an element face and its copy in the shell stay identical.
  std::vector<Vec3> pool;
  weld_faces(solid, kWeldTol, pool, true);
  const std::vector<Vec3> verts = shell_vertices(solid);
  node_faces(solid, verts, kWeldTol);
  for (auto& e : b.elements) {
    std::vector<double> level;  // an outer ceiling is horizontal: welding must not tilt it
    for (const auto& f : e.faces) level.push_back(f.ring.empty() ? 0.0 : f.ring[0].z());
    weld_faces(e.faces, kWeldTol, pool, false);
    node_faces(e.faces, verts, kWeldTol);
    if (e.type == ElementType::OuterCeiling)
      for (size_t i = 0; i < e.faces.size(); ++i) set_height(e.faces[i], level[i]);
    // A face the weld left a line (a step wall's sliver whose ends met) has
    // no area; the shell has dropped its copy, and no polygon can hold it.
    e.faces.erase(std::remove_if(e.faces.begin(), e.faces.end(), [](const Face& f) { return f.ring.size() < 3; }),
                  e.faces.end());
  }
  b.elements.erase(std::remove_if(b.elements.begin(), b.elements.end(),
                                  [](const Element& e) { return e.faces.empty(); }),
                   b.elements.end());
  b.solid = std::move(solid);
  if (log::enabled(log::Level::Debug)) debug_open_edges(b);
  return b;
}

}  // namespace c3d
