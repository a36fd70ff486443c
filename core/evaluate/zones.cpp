#include "core/evaluate/zones.h"

#include <memory>

namespace c3d {
namespace {

// FaceIndex works in its own local origin: world coordinates keep precision.
std::unique_ptr<FaceIndex> index_of(const std::vector<Face>& faces) {
  return faces.empty() ? nullptr : std::make_unique<FaceIndex>(faces);
}

// Every zone's roofs, tagged by zone: whose roof stands over a wall point.
std::unique_ptr<FaceIndex> roofs_by_zone(const std::vector<ZoneInput>& zones) {
  if (zones.size() < 2) return nullptr;
  std::vector<Face> faces;
  std::vector<int> owner;
  for (size_t z = 0; z < zones.size(); ++z) {
    faces.insert(faces.end(), zones[z].roof_faces.begin(), zones[z].roof_faces.end());
    owner.insert(owner.end(), zones[z].roof_faces.size(), int(z));
  }
  return faces.empty() ? nullptr : std::make_unique<FaceIndex>(faces, owner);
}

// The points' distances to the faces; without faces they only count as unmodelled.
void measure_surface(std::vector<Vec3> points, const FaceIndex* index, SurfaceMeasure& out) {
  if (points.empty()) return;
  if (!index) {
    out.unmodelled = long(points.size());
    return;
  }
  for (const auto& h : index->nearest(points)) out.distance.push_back(h.distance);
  out.points = std::move(points);
}

// Each wall point's vertical distance to the zone's own roof and to another zone's.
void place_wall_points(ZoneMeasure& zone, int zone_index, const FaceIndex* own_roofs,
                       const FaceIndex* all_roofs) {
  const std::vector<Vec3>& pts = zone.wall.points;
  zone.own_roof.assign(pts.size(), kNaN);
  zone.other_roof.assign(pts.size(), kNaN);
  if (own_roofs) {
    const auto hits = own_roofs->vertical(pts);
    for (size_t i = 0; i < pts.size(); ++i) zone.own_roof[i] = hits[i].distance;
  }
  if (all_roofs) {  // counts only where the zone's own roof is not over the point, so it is another's
    const auto hits = all_roofs->vertical(pts);
    for (size_t i = 0; i < pts.size(); ++i)
      if (hits[i].owner != zone_index) zone.other_roof[i] = hits[i].distance;
  }
}

ZoneMeasure measure_zone(ZoneInput& in, int zone_index, const FaceIndex* all_roofs) {
  ZoneMeasure z;
  z.id = in.id;
  z.roof.faces = in.roof_faces.size();
  z.wall.faces = in.wall_faces.size();
  const auto roofs = index_of(in.roof_faces), walls = index_of(in.wall_faces);
  measure_surface(std::move(in.roof_points), roofs.get(), z.roof);
  if (!z.roof.points.empty())
    for (const auto& h : roofs->vertical(z.roof.points)) z.roof_vertical.push_back(h.distance);
  measure_surface(std::move(in.wall_points), walls.get(), z.wall);
  if (!z.wall.points.empty()) place_wall_points(z, zone_index, roofs.get(), all_roofs);
  return z;
}

template <class Part>
Deviation pool_of(const std::vector<ZoneSummary>& zones, Part part) {
  std::vector<Deviation> parts;
  for (const ZoneSummary& z : zones) parts.push_back(part(z));
  return pool(parts);
}

}  // namespace

std::vector<ZoneMeasure> measure_zones(std::vector<ZoneInput> zones) {
  const auto all_roofs = roofs_by_zone(zones);
  std::vector<ZoneMeasure> out;
  for (size_t z = 0; z < zones.size(); ++z) out.push_back(measure_zone(zones[z], int(z), all_roofs.get()));
  return out;
}

ModelEvaluation evaluate_as_one_zone(const std::vector<MeshGroup>& model, const RoofWallPoints& points) {
  ZoneInput all{"all", {}, {}, points.roof, points.wall};
  for (const auto& g : model)
    for (const auto& f : g.faces) {
      if (f.ring.size() < 3) continue;
      const SurfaceKind kind = surface_kind(g, f);
      if (kind == SurfaceKind::Roof) all.roof_faces.push_back(f);
      else if (kind == SurfaceKind::Wall) all.wall_faces.push_back(f);
    }
  ModelEvaluation e;
  e.roof_points = points.roof.size();
  e.wall_points = points.wall.size();
  std::vector<ZoneInput> zones;
  zones.push_back(std::move(all));
  e.zones = measure_zones(std::move(zones));
  return e;
}

ZoneSummary summarize(const ZoneMeasure& zone) {
  ZoneSummary s;
  s.id = zone.id;
  s.roof = deviation(zone.roof.distance);
  s.roof_vertical = deviation(zone.roof_vertical);
  s.wall = deviation(zone.wall.distance);
  s.roof_cover = split_by_cover(zone.roof.distance, zone.roof_vertical);
  s.wall_cover = split_wall_cover(zone.wall.distance, zone.own_roof, zone.other_roof);
  s.roof_faces = zone.roof.faces;
  s.wall_faces = zone.wall.faces;
  s.unmodelled_roof = zone.roof.unmodelled;
  s.unmodelled_wall = zone.wall.unmodelled;
  return s;
}

ZoneSummary pool_zones(const std::vector<ZoneSummary>& zones) {
  using Z = const ZoneSummary&;
  ZoneSummary p;
  p.id = "pooled";
  p.roof = pool_of(zones, [](Z z) { return z.roof; });
  p.roof_vertical = pool_of(zones, [](Z z) { return z.roof_vertical; });
  p.wall = pool_of(zones, [](Z z) { return z.wall; });
  p.roof_cover = {pool_of(zones, [](Z z) { return z.roof_cover.on_model; }),
                  pool_of(zones, [](Z z) { return z.roof_cover.off_model; }),
                  pool_of(zones, [](Z z) { return z.roof_cover.uncovered; })};
  p.wall_cover = {pool_of(zones, [](Z z) { return z.wall_cover.on_wall; }),
                  pool_of(zones, [](Z z) { return z.wall_cover.under_own_roof; }),
                  pool_of(zones, [](Z z) { return z.wall_cover.under_other_roof; }),
                  pool_of(zones, [](Z z) { return z.wall_cover.under_no_roof; })};
  for (Z z : zones) {
    p.roof_faces += z.roof_faces;
    p.wall_faces += z.wall_faces;
    p.unmodelled_roof += z.unmodelled_roof;
    p.unmodelled_wall += z.unmodelled_wall;
  }
  return p;
}

EvaluationSummary summarize(const ModelEvaluation& evaluation) {
  EvaluationSummary s;
  for (const ZoneMeasure& z : evaluation.zones) s.zones.push_back(summarize(z));
  s.pooled = pool_zones(s.zones);
  return s;
}

}  // namespace c3d
