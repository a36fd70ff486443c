#include "core/geometry/geos_util.h"

#include <geos/geom/CoordinateSequence.h>
#include <geos/geom/LinearRing.h>
#include <geos/geom/MultiPolygon.h>
#include <geos/geom/Polygon.h>

#include <algorithm>

#include "core/geometry/geometry.h"

namespace c3d {
namespace {

using namespace geos::geom;

std::unique_ptr<LinearRing> ring_to_geos(const Ring2& r, const GeometryFactory& f) {
  std::vector<Coordinate> coords;
  coords.reserve(r.size() + 1);
  for (const Vec2& v : r) coords.emplace_back(v.x(), v.y());
  if (!r.empty()) coords.emplace_back(r.front().x(), r.front().y());
  return f.createLinearRing(std::move(coords));
}

Ring2 ring_from_geos(const LinearRing& ring, bool ccw) {
  const CoordinateSequence* seq = ring.getCoordinatesRO();
  Ring2 r;
  for (size_t i = 0; i + 1 < seq->size(); ++i) r.emplace_back(seq->getX(i), seq->getY(i));
  if ((signed_area(r) > 0) != ccw) std::reverse(r.begin(), r.end());
  return r;
}

void collect(const Geometry& g, MultiPolygon2& out) {
  if (auto* p = dynamic_cast<const Polygon*>(&g)) {
    if (p->isEmpty()) return;
    Polygon2 poly{ring_from_geos(*p->getExteriorRing(), true), {}};
    for (size_t i = 0; i < p->getNumInteriorRing(); ++i)
      poly.holes.push_back(ring_from_geos(*p->getInteriorRingN(i), false));
    out.push_back(std::move(poly));
    return;
  }
  for (size_t i = 0; i < g.getNumGeometries(); ++i)
    if (g.getGeometryN(i) != &g) collect(*g.getGeometryN(i), out);
}

}  // namespace

std::unique_ptr<Geometry> to_geos(const MultiPolygon2& shape, const GeometryFactory& f) {
  std::vector<std::unique_ptr<Polygon>> polys;
  for (const Polygon2& p : shape) {
    std::vector<std::unique_ptr<LinearRing>> holes;
    for (const Ring2& h : p.holes) holes.push_back(ring_to_geos(h, f));
    polys.push_back(f.createPolygon(ring_to_geos(p.outer, f), std::move(holes)));
  }
  if (polys.size() == 1) return std::move(polys[0]);
  return f.createMultiPolygon(std::move(polys));
}

MultiPolygon2 from_geos(const Geometry& g) {
  MultiPolygon2 out;
  collect(g, out);
  return out;
}

}  // namespace c3d
