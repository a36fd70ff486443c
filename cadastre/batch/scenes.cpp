#include "cadastre/batch/scenes.h"

#include "cadastre/batch/chunks.h"

#include <algorithm>
#include <cmath>
#include <tuple>

#include "core/evaluate/evaluate.h"
#include "core/reconstruct/ownership/ownership.h"

namespace c3d {
namespace {

MultiPolygon2 to_local(const MultiPolygon2& mp, const LocalFrame& f) {
  MultiPolygon2 out = mp;
  for (auto& p : out) {
    for (auto& v : p.outer) v = f.to_local(v);
    for (auto& h : p.holes)
      for (auto& v : h) v = f.to_local(v);
  }
  return out;
}

std::pair<Vec2, Vec2> bbox(const MultiPolygon2& mp) {
  Vec2 lo(1e300, 1e300), hi(-1e300, -1e300);
  for (const auto& p : mp)
    for (const auto& v : p.outer) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  return {lo, hi};
}

void move_faces(std::vector<Face>& faces, const Vec3& d) {
  for (auto& f : faces) {
    for (auto& v : f.ring) v += d;
    for (auto& h : f.holes)
      for (auto& v : h) v += d;
  }
}

void move_building(Building& b, const Vec3& d) {
  for (auto& e : b.elements) move_faces(e.faces, d);
  move_faces(b.solid, d);
  for (auto& l : b.lower_lods) move_faces(l.faces, d);
  for (auto& part : b.exact.parts) {
    part.origin += d;
    for (auto& q : part.roof.poles) q += d;
  }
}

// Parcels whose buffered boxes overlap: the candidates for shared roofs.
std::vector<std::vector<int>> neighbour_lists(const ParcelLayer& layer, double reach) {
  size_t n = layer.parcels.size();
  std::vector<std::pair<Vec2, Vec2>> boxes(n);
  for (size_t i = 0; i < n; ++i) boxes[i] = bbox(layer.parcels[i].shape);
  std::vector<int> order(n);
  for (size_t i = 0; i < n; ++i) order[i] = int(i);
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return boxes[a].first.x() < boxes[b].first.x(); });
  std::vector<std::vector<int>> out(n);
  for (size_t a = 0; a < n; ++a) {
    int i = order[a];
    for (size_t b = a + 1; b < n; ++b) {
      int j = order[b];
      if (boxes[j].first.x() > boxes[i].second.x() + reach) break;
      if (boxes[j].first.y() > boxes[i].second.y() + reach ||
          boxes[i].first.y() > boxes[j].second.y() + reach)
        continue;
      out[i].push_back(j);
      out[j].push_back(i);
    }
  }
  return out;
}

// One order for one set of points, whatever order the files hold them in:
// region growing and the neighbour searches under it break ties by point
// order, so the same points saved in another order gave other models (a
// shuffle of cimahi.las changed 27 of its 30 buildings). Rows of 2 m cells,
// then coordinates within a cell: points near one another stay near in
// memory, which the searches need to run fast (a plain x-y-z order slowed
// Cimahi's reconstruction from 2.5 to 3.0 s).
std::vector<size_t> in_one_order(std::vector<size_t> idx, const std::vector<Vec3>& pts) {
  auto key = [&](size_t k) {
    const Vec3& p = pts[k];
    return std::make_tuple(std::floor(p.y() / 2.0), std::floor(p.x() / 2.0), p.x(), p.y(), p.z());
  };
  std::sort(idx.begin(), idx.end(), [&](size_t a, size_t b) { return key(a) < key(b); });
  return idx;
}

}  // namespace

SceneGeometry scene_geometry(const ParcelLayer& layer, const ClipParams& clip) {
  // Wall points reach as far as the deviation counts them, at least.
  ClipParams wall_reach = clip;
  wall_reach.overhang_buffer_m = std::max(wall_reach.overhang_buffer_m, kWallPointReachM);
  ClipParams context = clip;
  context.overhang_buffer_m += kOwnershipContextM;
  return {context, wall_reach,
          neighbour_lists(layer, 2.0 * (clip.overhang_buffer_m + kOwnershipContextM) + 0.5), clip.overhang_buffer_m,
          std::max(context.overhang_buffer_m, wall_reach.overhang_buffer_m)};
}

SceneSource prepare_scenes(const LoadedInputs& in, const RegionPoints& points, const Box& box,
                           const SceneGeometry& geometry, const LocalFrame& frame) {
  SceneSource s;
  s.inputs = &in;
  s.points = &points;
  s.geometry = &geometry;
  s.frame = frame;
  const auto clipper = [&](const ClipParams& p) {
    return ParcelClipper(in.layer, p, in.boxes.touching(box, p.overhang_buffer_m));
  };
  s.wall_lists = clipper(geometry.wall_reach).clip(points.wall);
  s.roof_lists = clipper(geometry.roof_context).clip(points.roof);
  return s;
}

LocalFrame parcel_frame(const Parcel& p, const LocalFrame& batch) {
  const Vec2 lo = bbox(p.shape).first;
  LocalFrame f = batch;
  f.origin.head<2>() = Vec2(std::floor(lo.x() / 10) * 10, std::floor(lo.y() / 10) * 10);
  return f;
}

void move_result(ParcelResult& r, const LocalFrame& from, const LocalFrame& to) {
  const Vec3 d = from.origin - to.origin;
  if (d == Vec3::Zero()) return;
  for (auto& b : r.buildings) move_building(b, d);
}

ParcelScene make_scene(const SceneSource& src, size_t i) {
  const LoadedInputs& in = *src.inputs;
  const RegionPoints& pts = *src.points;
  const SceneGeometry& g = *src.geometry;
  const Parcel& p = in.layer.parcels[i];
  const LocalFrame frame = parcel_frame(p, src.frame);
  ParcelScene s;
  s.parcel_index = int(i);
  s.parcel_id = p.id;
  s.parcel = to_local(p.shape, frame);
  for (int n : g.neighbours[i]) s.neighbours.push_back(to_local(in.layer.parcels[n].shape, frame));
  for (size_t k : in_one_order(src.roof_lists[i], pts.roof)) s.roof_points.push_back(frame.to_local(pts.roof[k]));
  for (size_t k : in_one_order(src.wall_lists[i], pts.wall)) s.wall_points.push_back(frame.to_local(pts.wall[k]));
  s.overhang_buffer_m = g.overhang_buffer_m;
  s.context_m = g.overhang_buffer_m + kOwnershipContextM;
  s.roof_density = {roof_cell(Vec2(frame.origin.x(), frame.origin.y())), src.density};
  const Dtm* dtm = src.terrain ? src.terrain : &in.dtm;
  Vec3 o = frame.origin;
  s.terrain = [dtm, o](double x, double y) { return dtm->height_at(x + o.x(), y + o.y()) - o.z(); };
  return s;
}

}  // namespace c3d
