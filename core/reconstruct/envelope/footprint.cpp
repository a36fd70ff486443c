#include "core/reconstruct/envelope/footprint.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <utility>

#include "core/geometry/geometry.h"
#include "core/geometry/polygon_ops.h"
#include "core/reconstruct/envelope/common.h"
#include "core/reconstruct/outline/outline.h"

namespace c3d::envelope {

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
// Parts of the moved-edge ring smaller than this are where moved lines cross
// each other (a short edge's line overtaken by its neighbours'), not floor.
constexpr double kMinMovedPart = 0.5;  // m^2
// The footprint is regularised (regularize_polygon) dropping edges shorter
// than this: chamfers and jogs the moved outline edges leave, which no wall makes.
constexpr double kRegularizeEdge = 1.0;  // m
// A lobe split off a pinched ring with less area than this is a spike of no
// width, not a part.
constexpr double kMinLobeArea = 1e-6;  // m^2
// The terrain under the footprint is averaged on a grid of this cell (and at
// its corners): fine enough for a house's ground, few look-ups.
constexpr double kTerrainCell = 0.5;  // m

namespace {

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

}  // namespace

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
    if (!split && r.size() >= 3 && std::abs(signed_area(r)) > kMinLobeArea) done.push_back(r);
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

// Edges shorter than kSpeckM go, each by the end whose removal moves the
// footprint least.
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
Polygon2 footprint_from_edges(const std::vector<OutlineEdge>& edges, const Polygon2& outline,
                              double default_overhang, FootprintApart* apart) {
  Ring2 ring;
  bool stepped = false;
  size_t n = edges.size();
  for (size_t i = 0; i < n; ++i) {
    const OutlineEdge& p = edges[(i + n - 1) % n];
    const OutlineEdge& c = edges[i];
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
  MultiPolygon2 valid = poly::drop_small(poly::make_valid({Polygon2{ring, {}}}), kMinMovedPart);
  valid = separate_pinched(poly::intersect(valid, {outline}));
  if (valid.empty()) valid = poly::buffer({outline}, -default_overhang);
  if (valid.empty()) throw std::runtime_error("roof outline too small for a footprint");
  Polygon2 best = poly::largest(valid);
  best.holes.clear();
  if (apart) {
    for (const Polygon2& part : valid)
      if (area(part) >= kMinFootprintPart) apart->parts.push_back(part);
    std::sort(apart->parts.begin(), apart->parts.end(),
              [](const Polygon2& a, const Polygon2& b) { return area(a) > area(b); });
    for (const OutlineEdge& e : edges) apart->overhang = std::max(apart->overhang, e.overhang);
  }
  // Regularising would merge the lines of a step (0.3 m apart or less) and
  // give the whole side one overhang and one kind of wall; a stepped ring
  // that pinches (passes twice through a vertex) is regularised all the same.
  if (stepped && !pinched(best.outer)) return best;
  // Regularising may push a corner past the roof outline; the walls must stay
  // under the roof, or the roof would not close the solid there.
  MultiPolygon2 under = separate_pinched(poly::intersect({regularize_polygon(best, kRegularizeEdge)}, {outline}));
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
  for (double x = lo.x() + 0.5 * kTerrainCell; x < hi.x(); x += kTerrainCell)
    for (double y = lo.y() + 0.5 * kTerrainCell; y < hi.y(); y += kTerrainCell) {
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

}  // namespace c3d::envelope
