#include "cadastre/parcel_checks.h"

#include <algorithm>
#include <cstdio>
#include <set>

#include "core/error.h"
#include "core/geometry/geometry.h"
#include "core/geometry/polygon_ops.h"

namespace c3d {
namespace {

// Neighbours digitised along one shared edge overlap by slivers of a few
// square centimetres; an overlap a building could stand on is far larger.
constexpr double kMinOverlapM2 = 0.5;

struct Box {
  Vec2 lo{1e300, 1e300}, hi{-1e300, -1e300};
};

Box box_of(const MultiPolygon2& shape) {
  Box b;
  for (const auto& poly : shape)
    for (const auto& v : poly.outer) b.lo = b.lo.cwiseMin(v), b.hi = b.hi.cwiseMax(v);
  return b;
}

}  // namespace

std::vector<ParcelOverlap> parcel_overlaps(const ParcelLayer& layer) {
  const auto& parcels = layer.parcels;
  std::vector<Box> boxes;
  for (const auto& p : parcels) boxes.push_back(box_of(p.shape));
  std::vector<size_t> order(parcels.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return boxes[a].lo.x() < boxes[b].lo.x(); });
  std::vector<ParcelOverlap> out;
  for (size_t k = 0; k < order.size(); ++k) {  // sweep along x: only boxes that meet are intersected
    const Box& a = boxes[order[k]];
    for (size_t m = k + 1; m < order.size() && boxes[order[m]].lo.x() < a.hi.x(); ++m) {
      const Box& b = boxes[order[m]];
      if (b.lo.y() >= a.hi.y() || a.lo.y() >= b.hi.y()) continue;
      const double shared = area(poly::intersect(parcels[order[k]].shape, parcels[order[m]].shape));
      if (shared > kMinOverlapM2)
        out.push_back({std::min(order[k], order[m]), std::max(order[k], order[m]), shared});
    }
  }
  std::sort(out.begin(), out.end(), [](const ParcelOverlap& x, const ParcelOverlap& y) {
    return std::make_pair(x.a, x.b) < std::make_pair(y.a, y.b);
  });
  return out;
}

std::vector<std::string> overlap_warnings(const ParcelLayer& layer) {
  std::vector<std::string> out;
  for (const ParcelOverlap& o : parcel_overlaps(layer)) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.2f", o.area);
    out.push_back(layer.source + ": parcels " + layer.parcels[o.a].id + " and " + layer.parcels[o.b].id +
                  " overlap by " + buf + " m2; points in the overlap count for both, so a building there "
                  "is modelled and valued in each (docs/inputs.md)");
  }
  return out;
}

void check_override_ids(const std::map<std::string, ParcelValuationOverride>& overrides, const ParcelLayer& layer,
                        const std::string& config_source, bool selected, std::vector<std::string>& warnings) {
  std::set<std::string> ids;
  for (const auto& p : layer.parcels) ids.insert(p.id);
  for (const auto& [id, override] : overrides) {
    if (ids.count(id)) continue;
    const std::string where = config_source.empty() ? "config" : config_source;
    const std::string problem = "[valuation.parcels] names parcel '" + id + "', which is not in " + layer.source;
    if (!selected) throw InputError(where, problem);
    warnings.push_back(where + ": " + problem + " as selected by --where/--bbox");
  }
}

}  // namespace c3d
