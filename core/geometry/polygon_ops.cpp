#include "core/geometry/polygon_ops.h"

#include <geos/algorithm/hull/ConcaveHull.h>
#include <geos/geom/CoordinateArraySequence.h>
#include <geos/geom/GeometryFactory.h>
#include <geos/geom/LineString.h>
#include <geos/geom/LinearRing.h>
#include <geos/geom/MultiPoint.h>
#include <geos/geom/MultiPolygon.h>
#include <geos/geom/Point.h>
#include <geos/geom/Polygon.h>
#include <geos/operation/buffer/BufferOp.h>
#include <geos/operation/buffer/BufferParameters.h>
#include <geos/operation/distance/IndexedFacetDistance.h>
#include <geos/geom/PrecisionModel.h>
#include <geos/operation/linemerge/LineMerger.h>
#include <geos/operation/overlayng/UnaryUnionNG.h>
#include <geos/operation/polygonize/Polygonizer.h>
#include <geos/operation/union/UnaryUnionOp.h>
#include <geos/operation/valid/MakeValid.h>
#include <geos/simplify/DouglasPeuckerSimplifier.h>
#include <geos/simplify/TopologyPreservingSimplifier.h>
#include <geos/triangulate/VoronoiDiagramBuilder.h>

#include <algorithm>
#include <cmath>

#include "core/geometry/geometry.h"
#include "core/geometry/geos_util.h"

namespace c3d::poly {

using geos::geom::Coordinate;
using geos::geom::CoordinateArraySequence;
using geos::geom::Geometry;
using geos::geom::GeometryFactory;
using GeomPtr = std::unique_ptr<Geometry>;

namespace {

const GeometryFactory& factory() {
  static GeometryFactory::Ptr f = GeometryFactory::create();
  return *f;
}

// Degenerate rings (fewer than 3 vertices) are left out rather than thrown on:
// stage results may hold them.
GeomPtr to_geos(const MultiPolygon2& mp) {
  MultiPolygon2 clean;
  for (const auto& p : mp) {
    if (p.outer.size() < 3) continue;
    Polygon2 q{p.outer, {}};
    for (const auto& h : p.holes)
      if (h.size() >= 3) q.holes.push_back(h);
    clean.push_back(std::move(q));
  }
  return c3d::to_geos(clean, factory());
}

MultiPolygon2 from_geos(const Geometry* g) {
  if (!g) return {};
  return drop_small(c3d::from_geos(*g), 1e-8);
}

// Overlay that survives GEOS topology exceptions on near-degenerate input.
template <class Op>
MultiPolygon2 overlay(const MultiPolygon2& a, const MultiPolygon2& b, Op op) {
  auto ga = to_geos(a), gb = to_geos(b);
  try {
    return from_geos(op(ga.get(), gb.get()).get());
  } catch (const std::exception&) {
    auto va = ga->buffer(0), vb = gb->buffer(0);
    return from_geos(op(va.get(), vb.get()).get());
  }
}

}  // namespace

MultiPolygon2 unite(const MultiPolygon2& a, const MultiPolygon2& b) {
  return overlay(a, b, [](const Geometry* x, const Geometry* y) { return x->Union(y); });
}

MultiPolygon2 unite_all(const std::vector<MultiPolygon2>& parts) {
  MultiPolygon2 all;
  for (const auto& p : parts) all.insert(all.end(), p.begin(), p.end());
  auto g = to_geos(all);
  try {
    return from_geos(g->Union().get());
  } catch (const std::exception&) {
    return from_geos(g->buffer(0).get());
  }
}

MultiPolygon2 intersect(const MultiPolygon2& a, const MultiPolygon2& b) {
  return overlay(a, b, [](const Geometry* x, const Geometry* y) { return x->intersection(y); });
}

MultiPolygon2 subtract(const MultiPolygon2& a, const MultiPolygon2& b) {
  return overlay(a, b, [](const Geometry* x, const Geometry* y) { return x->difference(y); });
}

namespace {
// Mitred joins keep the square corners of buildings square.
geos::operation::buffer::BufferParameters mitre_parameters() {
  geos::operation::buffer::BufferParameters params;
  params.setJoinStyle(geos::operation::buffer::BufferParameters::JOIN_MITRE);
  params.setMitreLimit(4.0);
  return params;
}
}  // namespace

namespace {
MultiPolygon2 buffer_together(const MultiPolygon2& a, double distance) {
  auto params = mitre_parameters();  // BufferOp takes it by non-const reference
  auto g = to_geos(a);
  return from_geos(geos::operation::buffer::BufferOp::bufferOp(g.get(), distance, params).get());
}
}  // namespace

// GEOS (3.11) buffers the parts of a multipolygon in one graph, and the raw
// offset curves of a wide part and of a sliver wedge near it can leave that
// graph unable to place a hole ("unable to assign hole to a shell") though
// the input is valid. Shrinking needs no such graph: a disc inside a valid
// multipolygon lies inside one part (parts meet at points at most), so its
// erosion is its parts' erosions side by side, each done alone.
MultiPolygon2 buffer(const MultiPolygon2& a, double distance) {
  if (distance >= 0 || a.size() < 2 || !is_valid(a)) return buffer_together(a, distance);
  MultiPolygon2 out;
  for (const auto& p : a)
    for (auto& q : buffer_together({p}, distance)) out.push_back(std::move(q));
  return out;
}

namespace {
std::unique_ptr<geos::geom::LineString> line_string(const std::vector<Vec2>& line) {
  auto seq = std::make_unique<CoordinateArraySequence>();
  for (const auto& p : line) seq->add(Coordinate(p.x(), p.y()));
  return factory().createLineString(std::move(seq));
}
}  // namespace

MultiPolygon2 buffer_line(const std::vector<Vec2>& line, double distance) {
  return from_geos(line_string(line)->buffer(distance, 4).get());
}

std::vector<Vec2> simplify_line(const std::vector<Vec2>& line, double tolerance) {
  auto g = geos::simplify::DouglasPeuckerSimplifier::simplify(line_string(line).get(), tolerance);
  std::vector<Vec2> out;
  auto coords = g->getCoordinates();
  for (size_t i = 0; i < coords->size(); ++i) out.emplace_back(coords->getX(i), coords->getY(i));
  return out;
}

MultiPolygon2 side_strip(const std::vector<Vec2>& line, double width) {
  auto params = mitre_parameters();
  params.setSingleSided(true);
  params.setEndCapStyle(geos::operation::buffer::BufferParameters::CAP_FLAT);
  auto ls = line_string(line);
  return from_geos(geos::operation::buffer::BufferOp::bufferOp(ls.get(), width, params).get());
}

MultiPolygon2 simplify(const MultiPolygon2& a, double tolerance) {
  auto g = to_geos(a);
  return from_geos(geos::simplify::TopologyPreservingSimplifier::simplify(g.get(), tolerance).get());
}

MultiPolygon2 make_valid(const MultiPolygon2& a) {
  auto g = to_geos(a);
  if (g->isValid()) return from_geos(g.get());
  geos::operation::valid::MakeValid mv;
  return from_geos(mv.build(g.get()).get());
}

bool is_valid(const MultiPolygon2& a) { return to_geos(a)->isValid(); }

namespace {

std::unique_ptr<geos::geom::MultiPoint> multipoint(const std::vector<Vec2>& points) {
  std::vector<Coordinate> coords;
  coords.reserve(points.size());
  for (const auto& p : points) coords.emplace_back(p.x(), p.y());
  return std::unique_ptr<geos::geom::MultiPoint>(factory().createMultiPoint(coords));
}

}  // namespace

MultiPolygon2 concave_hull(const std::vector<Vec2>& points, double max_edge) {
  auto hull = geos::algorithm::hull::ConcaveHull::concaveHullByLength(multipoint(points).get(), max_edge);
  return from_geos(hull.get());
}

MultiPolygon2 convex_hull(const std::vector<Vec2>& points) { return from_geos(multipoint(points)->convexHull().get()); }

Polygon2 largest(const MultiPolygon2& mp) {
  if (mp.empty()) return {};
  return *std::max_element(mp.begin(), mp.end(),
                           [](const auto& a, const auto& b) { return area(a) < area(b); });
}

MultiPolygon2 drop_small(const MultiPolygon2& a, double min_area) {
  MultiPolygon2 out;
  for (const auto& p : a) {
    if (std::abs(signed_area(p.outer)) < min_area) continue;
    Polygon2 q{p.outer, {}};
    for (const auto& h : p.holes)
      if (std::abs(signed_area(h)) >= min_area) q.holes.push_back(h);
    out.push_back(std::move(q));
  }
  return out;
}

namespace {
Ring2 without_needles(Ring2 r, double cos_max) {
  for (bool dropped = true; dropped && r.size() > 3;) {  // a tip gone may leave another
    dropped = false;
    for (size_t i = 0; i < r.size() && r.size() > 3; ++i) {
      const Vec2& v = r[i];
      const Vec2 a = r[(i + r.size() - 1) % r.size()] - v, b = r[(i + 1) % r.size()] - v;
      const double na = a.norm(), nb = b.norm();
      if (na < 1e-12 || nb < 1e-12 || a.dot(b) > cos_max * na * nb) {
        r.erase(r.begin() + long(i));
        dropped = true;
      }
    }
  }
  return r;
}
}  // namespace

MultiPolygon2 drop_needles(const MultiPolygon2& a, double max_angle) {
  const double cos_max = std::cos(max_angle);
  MultiPolygon2 out;
  for (const auto& p : a) {
    Polygon2 q{without_needles(p.outer, cos_max), {}};
    for (const auto& h : p.holes) q.holes.push_back(without_needles(h, cos_max));
    out.push_back(std::move(q));
  }
  return out;
}

bool covers(const MultiPolygon2& a, const Vec2& p) {
  auto winding = [&](const Ring2& r) {
    bool in = false;
    for (size_t i = 0, j = r.size() - 1; i < r.size(); j = i++) {
      if ((r[i].y() > p.y()) != (r[j].y() > p.y()) &&
          p.x() < (r[j].x() - r[i].x()) * (p.y() - r[i].y()) / (r[j].y() - r[i].y()) + r[i].x())
        in = !in;
    }
    return in;
  };
  for (const auto& poly : a) {
    if (!winding(poly.outer)) continue;
    bool in_hole = false;
    for (const auto& h : poly.holes) in_hole = in_hole || winding(h);
    if (!in_hole) return true;
  }
  return false;
}

double distance(const MultiPolygon2& a, const Vec2& p) {
  if (covers(a, p)) return 0.0;
  double best = 1e300;
  auto ring_distance = [&](const Ring2& r) {
    for (size_t i = 0; i < r.size(); ++i) {
      Vec2 u = r[i], v = r[(i + 1) % r.size()], d = v - u;
      double t = std::clamp((p - u).dot(d) / std::max(d.squaredNorm(), 1e-18), 0.0, 1.0);
      best = std::min(best, (u + t * d - p).norm());
    }
  };
  for (const auto& poly : a) {
    ring_distance(poly.outer);
    for (const auto& h : poly.holes) ring_distance(h);
  }
  return best;
}

MultiPolygon2 box(const Vec2& lo, const Vec2& hi) {
  return {Polygon2{{lo, {hi.x(), lo.y()}, hi, {lo.x(), hi.y()}}, {}}};
}

struct NearZone::Impl {
  GeomPtr zone;
};

NearZone::NearZone(const MultiPolygon2& b, double tolerance) : impl_(std::make_unique<Impl>()) {
  impl_->zone = to_geos(b)->buffer(tolerance, 2);
}
NearZone::~NearZone() = default;
NearZone::NearZone(NearZone&&) noexcept = default;
NearZone& NearZone::operator=(NearZone&&) noexcept = default;

std::vector<std::vector<Vec2>> NearZone::shared_with(const MultiPolygon2& a) const {
  auto ba = to_geos(a)->getBoundary();
  std::vector<std::vector<Vec2>> out;
  GeomPtr shared;
  try {
    shared = ba->intersection(impl_->zone.get());
  } catch (const std::exception&) {
    return out;
  }
  geos::operation::linemerge::LineMerger merger;
  merger.add(shared.get());
  for (auto& ls : merger.getMergedLineStrings()) {
    std::vector<Vec2> line;
    const auto* seq = ls->getCoordinatesRO();
    for (size_t i = 0; i < seq->size(); ++i) line.emplace_back(seq->getX(i), seq->getY(i));
    if (line.size() >= 2) out.push_back(std::move(line));
  }
  return out;
}

std::vector<std::vector<Vec2>> shared_boundary(const MultiPolygon2& a, const MultiPolygon2& b,
                                               double tolerance) {
  return NearZone(b, tolerance).shared_with(a);
}

MultiPolygon2 planar_faces(const MultiPolygon2& shapes, double grid) {
  std::vector<GeomPtr> lines;
  auto add_ring = [&](const Ring2& r) {
    if (r.size() < 3) return;
    auto seq = std::make_unique<CoordinateArraySequence>();
    for (const auto& v : r) seq->add(Coordinate(v.x(), v.y()));
    seq->add(Coordinate(r[0].x(), r[0].y()));
    lines.push_back(factory().createLineString(std::move(seq)));
  };
  for (const auto& p : shapes) {
    add_ring(p.outer);
    for (const auto& h : p.holes) add_ring(h);
  }
  if (lines.empty()) return {};
  auto all = factory().createMultiLineString(std::move(lines));
  // nodes every crossing and shared stretch; on a grid by snap rounding
  GeomPtr noded = grid > 0 ? geos::operation::overlayng::UnaryUnionNG::Union(
                                 all.get(), geos::geom::PrecisionModel(1.0 / grid))
                           : all->Union();
  geos::operation::polygonize::Polygonizer polygonizer;
  polygonizer.add(static_cast<const Geometry*>(noded.get()));
  MultiPolygon2 out;
  for (auto& face : polygonizer.getPolygons())
    for (auto& p : c3d::from_geos(*face)) out.push_back(std::move(p));
  return out;
}

Vec2 interior_point(const Polygon2& p) {
  auto g = to_geos(MultiPolygon2{p});
  auto pt = g->getInteriorPoint();
  if (!pt || pt->isEmpty()) return p.outer.empty() ? Vec2::Zero() : p.outer[0];
  return {pt->getX(), pt->getY()};
}

namespace {

// Points every `step` along the rings of mp within `reach` of other's
// boundary, leaving out those on it (a shared corner is nobody's site).
void boundary_sites(const MultiPolygon2& mp, const MultiPolygon2& other, double reach, double step,
                    std::vector<Vec2>& out) {
  const GeomPtr rim = to_geos(other)->getBoundary();
  const geos::operation::distance::IndexedFacetDistance to_rim(rim.get());
  auto walk = [&](const Ring2& r) {
    for (size_t i = 0; i < r.size(); ++i) {
      const Vec2 &p = r[i], &q = r[(i + 1) % r.size()];
      const int n = std::max(1, int(std::ceil((q - p).norm() / step)));
      for (int k = 0; k < n; ++k) {
        const Vec2 x = p + (q - p) * (double(k) / n);
        const std::unique_ptr<geos::geom::Point> pt(factory().createPoint(Coordinate(x.x(), x.y())));
        const double d = to_rim.distance(pt.get());
        if (d > 1e-6 && d <= reach) out.push_back(x);
      }
    }
  };
  for (const auto& poly : mp) {
    walk(poly.outer);
    for (const auto& h : poly.holes) walk(h);
  }
}

}  // namespace

MultiPolygon2 nearer_to(const MultiPolygon2& b, const MultiPolygon2& a, double reach, double step) {
  // Land within reach of b is nearest to b's sites within 2 x reach of a, or to
  // a's within 2 x reach of b, where it is nearer to a at all.
  std::vector<Vec2> sites;
  boundary_sites(b, a, 2 * reach + step, step, sites);
  const size_t from_b = sites.size();
  boundary_sites(a, b, 2 * reach + step, step, sites);
  if (from_b == 0 || from_b == sites.size()) return {};
  CoordinateArraySequence coords;
  for (const auto& x : sites) coords.add(Coordinate(x.x(), x.y()));
  const MultiPolygon2 near_b = buffer(b, reach);
  GeomPtr zone = to_geos(near_b);
  geos::geom::Envelope env(*zone->getEnvelopeInternal());
  geos::triangulate::VoronoiDiagramBuilder voronoi;
  voronoi.setSites(coords);
  voronoi.setClipEnvelope(&env);
  auto cells = voronoi.getDiagram(factory());
  std::vector<std::unique_ptr<Geometry>> mine;
  for (size_t c = 0; c < cells->getNumGeometries(); ++c) {
    const Geometry* cell = cells->getGeometryN(c);
    const auto inside = cell->getInteriorPoint();
    if (!inside || inside->isEmpty()) continue;
    const Vec2 q(inside->getX(), inside->getY());
    size_t best = 0;  // any point of a Voronoi cell is nearest to the cell's own site
    for (size_t i = 1; i < sites.size(); ++i)
      if ((sites[i] - q).squaredNorm() < (sites[best] - q).squaredNorm()) best = i;
    if (best < from_b) mine.push_back(cell->clone());
  }
  if (mine.empty()) return {};
  auto nearer = factory().createGeometryCollection(std::move(mine))->Union();
  return subtract(intersect(from_geos(nearer.get()), near_b), unite(a, b));
}

MultiPolygon2 halfplane_box(const Vec2& p, const Vec2& dir, const Vec2& side_point,
                            double extent) {
  Vec2 d = dir.normalized();
  Vec2 n(-d.y(), d.x());
  if (n.dot(side_point - p) < 0) n = -n;
  Ring2 r{p - d * extent, p + d * extent, p + d * extent + n * extent, p - d * extent + n * extent};
  if (signed_area(r) < 0) std::reverse(r.begin(), r.end());
  return {Polygon2{r, {}}};
}

}  // namespace c3d::poly
