#include "cadastre/clip.h"

#include <geos/algorithm/locate/PointOnGeometryLocator.h>
#include <geos/geom/Coordinate.h>
#include <geos/geom/Envelope.h>
#include <geos/geom/GeometryFactory.h>
#include <geos/geom/prep/PreparedGeometryFactory.h>
#include <geos/geom/prep/PreparedPolygon.h>
#include <geos/index/strtree/TemplateSTRtree.h>

#include <stdexcept>

#include "core/geometry/geos_util.h"
#include "core/error.h"

namespace c3d {

using geos::algorithm::locate::PointOnGeometryLocator;
using geos::geom::Coordinate;
using geos::geom::Envelope;
using geos::geom::Geometry;
using geos::geom::Location;
using geos::geom::prep::PreparedGeometry;
using geos::geom::prep::PreparedGeometryFactory;

namespace {

// The locator behind a prepared polygon tests a coordinate without building a
// GEOS Point per LiDAR point. Its index is built lazily, so it is warmed here.
PointOnGeometryLocator* locator_of(const PreparedGeometry& prepared) {
  auto* polygon = dynamic_cast<const geos::geom::prep::PreparedPolygon*>(&prepared);
  PointOnGeometryLocator* loc = polygon ? polygon->getPointLocator() : nullptr;
  if (loc) {
    Coordinate c(0, 0);
    loc->locate(&c);
  }
  return loc;
}

}  // namespace

struct ParcelClipper::Impl {
  struct Area {
    std::unique_ptr<Geometry> geometry;
    std::unique_ptr<PreparedGeometry> prepared;
    PointOnGeometryLocator* locator = nullptr;  // owned by prepared

    Location locate(double x, double y) const {
      Coordinate c(x, y);
      if (locator) return locator->locate(&c);
      // Multipolygons prepare as a generic geometry: locate through a point.
      std::unique_ptr<Geometry> point(geometry->getFactory()->createPoint(c));
      if (prepared->containsProperly(point.get())) return Location::INTERIOR;
      return prepared->covers(point.get()) ? Location::BOUNDARY : Location::EXTERIOR;
    }
  };
  geos::geom::GeometryFactory::Ptr factory = geos::geom::GeometryFactory::create();
  double buffer = 0;
  std::vector<Area> buffered, exact;
  // Built once in the constructor; queries then only read it.
  mutable geos::index::strtree::TemplateSTRtree<std::size_t> tree;

  static Area make_area(std::unique_ptr<Geometry> g) {
    Area a;
    a.prepared = PreparedGeometryFactory::prepare(g.get());
    a.locator = locator_of(*a.prepared);
    a.geometry = std::move(g);
    return a;
  }
};

namespace {
std::vector<std::size_t> every_parcel(const ParcelLayer& layer) {
  std::vector<std::size_t> all(layer.parcels.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
  return all;
}
}  // namespace

ParcelClipper::ParcelClipper(const ParcelLayer& layer, const ClipParams& params)
    : ParcelClipper(layer, params, every_parcel(layer)) {}

ParcelClipper::ParcelClipper(const ParcelLayer& layer, const ClipParams& params, const std::vector<std::size_t>& only)
    : impl_(std::make_unique<Impl>()) {
  impl_->buffer = params.overhang_buffer_m;
  if (!(impl_->buffer >= 0))
    throw InputError(layer.source, "overhang buffer must be >= 0 m");
  impl_->buffered.resize(layer.parcels.size());
  impl_->exact.resize(layer.parcels.size());
  for (std::size_t i : only) {
    std::unique_ptr<Geometry> shape = to_geos(layer.parcels.at(i).shape, *impl_->factory);
    std::unique_ptr<Geometry> grown = impl_->buffer > 0 ? shape->buffer(impl_->buffer, 8)
                                                        : shape->clone();
    impl_->tree.insert(*grown->getEnvelopeInternal(), i);
    impl_->buffered[i] = Impl::make_area(std::move(grown));
    impl_->exact[i] = Impl::make_area(std::move(shape));
  }
  impl_->tree.build();
}

ParcelClipper::~ParcelClipper() = default;
ParcelClipper::ParcelClipper(ParcelClipper&&) noexcept = default;
ParcelClipper& ParcelClipper::operator=(ParcelClipper&&) noexcept = default;

std::size_t ParcelClipper::parcel_count() const { return impl_->buffered.size(); }
double ParcelClipper::buffer_m() const { return impl_->buffer; }

void ParcelClipper::clip(const Vec3* pts, std::size_t n, IndexLists& lists,
                         std::size_t first_index) const {
  lists.resize(parcel_count());
  for (std::size_t i = 0; i < n; ++i) {
    const double x = pts[i].x(), y = pts[i].y();
    impl_->tree.query(Envelope(x, x, y, y), [&](std::size_t parcel) {
      if (impl_->buffered[parcel].locate(x, y) != Location::EXTERIOR)
        lists[parcel].push_back(first_index + i);
    });
  }
}

ParcelClipper::IndexLists ParcelClipper::clip(const std::vector<Vec3>& pts) const {
  IndexLists lists;
  clip(pts.data(), pts.size(), lists, 0);
  return lists;
}

bool ParcelClipper::inside(std::size_t parcel, double x, double y) const {
  const Impl::Area& a = impl_->exact.at(parcel);
  if (!a.geometry) throw std::logic_error("ParcelClipper::inside: parcel not among the clipper's");
  return a.locate(x, y) == Location::INTERIOR;
}

}  // namespace c3d
