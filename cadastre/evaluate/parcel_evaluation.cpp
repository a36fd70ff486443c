#include "cadastre/evaluate/parcel_evaluation.h"

#include <algorithm>

#include "cadastre/clip.h"

namespace c3d {
namespace {

// The parcel whose id is the longest prefix of the group name, followed by '_'
// or the end (building ids are "<parcel id>_b<k>"); -1 when none.
int parcel_named(const std::string& name, const ParcelLayer& layer) {
  int best = -1;
  size_t best_len = 0;
  for (size_t p = 0; p < layer.parcels.size(); ++p) {
    const std::string& id = layer.parcels[p].id;
    if (id.size() > best_len && name.compare(0, id.size(), id) == 0 &&
        (name.size() == id.size() || name[id.size()] == '_')) {
      best = int(p);
      best_len = id.size();
    }
  }
  return best;
}

// The parcel a group's face belongs to: by the group's name, else the parcel
// under the face centroid, else one whose buffer holds it; -1 when none.
int parcel_of(const MeshGroup& g, const Face& f, const ParcelLayer& layer, const ParcelClipper& clip) {
  const int named = parcel_named(g.name, layer);
  if (named >= 0) return named;
  Vec3 c = Vec3::Zero();
  for (const auto& p : f.ring) c += p;
  c /= double(f.ring.size());
  for (size_t p = 0; p < layer.parcels.size(); ++p)
    if (clip.inside(p, c.x(), c.y())) return int(p);
  auto lists = clip.clip(std::vector<Vec3>{c});  // in a buffer only
  for (size_t p = 0; p < lists.size(); ++p)
    if (!lists[p].empty()) return int(p);
  return -1;
}

// Sorts the model's roof and wall faces into the zones; returns the faces of no parcel.
long assign_faces(const std::vector<MeshGroup>& model, const ParcelLayer& layer, const ParcelClipper& clip,
                  std::vector<ZoneInput>& zones) {
  long outside = 0;
  for (const auto& g : model)
    for (const auto& f : g.faces) {
      if (f.ring.size() < 3) continue;
      const SurfaceKind kind = surface_kind(g, f);
      if (kind == SurfaceKind::Other) continue;
      const int z = parcel_of(g, f, layer, clip);
      if (z < 0) ++outside;
      else (kind == SurfaceKind::Roof ? zones[size_t(z)].roof_faces : zones[size_t(z)].wall_faces).push_back(f);
    }
  return outside;
}

// Hands each zone its points: with inside_only (roof points) those inside the
// parcel, else those within its buffer. Returns the points no zone takes.
long assign_points(const std::vector<Vec3>& pts, bool inside_only, const ParcelClipper& clip,
                   std::vector<ZoneInput>& zones, std::vector<Vec3> ZoneInput::*member) {
  const ParcelClipper::IndexLists lists = clip.clip(pts);
  std::vector<char> taken(pts.size(), 0);
  for (size_t z = 0; z < lists.size(); ++z)
    for (size_t i : lists[z])
      if (!inside_only || clip.inside(z, pts[i].x(), pts[i].y())) {
        taken[i] = 1;
        (zones[z].*member).push_back(pts[i]);
      }
  return long(std::count(taken.begin(), taken.end(), 0));
}

}  // namespace

ModelEvaluation evaluate_per_parcel(const std::vector<MeshGroup>& model, const RoofWallPoints& points,
                                    const ParcelLayer& layer, double wall_reach_m) {
  ClipParams params;
  params.overhang_buffer_m = wall_reach_m;
  const ParcelClipper clip(layer, params);
  std::vector<ZoneInput> zones(layer.parcels.size());
  for (size_t p = 0; p < zones.size(); ++p) zones[p].id = layer.parcels[p].id;
  ModelEvaluation e;
  e.per_parcel = true;
  e.faces_outside = assign_faces(model, layer, clip, zones);
  e.roof_points = points.roof.size();
  e.wall_points = points.wall.size();
  e.points_outside = assign_points(points.roof, true, clip, zones, &ZoneInput::roof_points) +
                     assign_points(points.wall, false, clip, zones, &ZoneInput::wall_points);
  e.zones = measure_zones(std::move(zones));
  return e;
}

}  // namespace c3d
