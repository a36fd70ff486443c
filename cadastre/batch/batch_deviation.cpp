#include "cadastre/batch/batch_deviation.h"

#include <cmath>
#include <limits>

#include "cadastre/batch/chunks.h"
#include "cadastre/batch/scenes.h"
#include "cadastre/clip.h"
#include "core/evaluate/evaluate.h"

namespace c3d {
namespace {

// Beyond its parcel's box, how far a model's faces may reach past the points
// it was modelled from (the overhang buffer and the ownership context): room
// for outlines regularised outward.
constexpr double kModelMarginM = 5.0;
// The first radius around a chunk searched for the nearest face; a point
// whose nearest face lies further is searched again at four times the radius.
constexpr double kFirstSearchM = 10.0;
constexpr size_t kNone = std::numeric_limits<size_t>::max();

std::vector<Face> world_faces(const BatchModel& model, const std::vector<ElementType>& types) {
  std::vector<Face> out;
  for (const auto& r : model.results)
    for (const auto& b : r.buildings)
      for (Face f : faces_of(b, types)) {
        for (auto& v : f.ring) v = model.frame.to_world(v);
        for (auto& h : f.holes)
          for (auto& v : h) v = model.frame.to_world(v);
        out.push_back(std::move(f));
      }
  return out;
}

std::vector<Ring3> footprint_rings(const BatchModel& model) {
  std::vector<Ring3> rings;
  for (const Face& f : world_faces(model, {ElementType::Ground})) rings.push_back(f.ring);
  return rings;
}

// The points this chunk counts: those whose lowest-indexed parcel (inside it
// strictly for roofs, within the clipper's reach for walls) is in the chunk,
// so that each point counts once in the batch; by parcel, then list order.
std::vector<Vec3> counted_points(const std::vector<Vec3>& pts, const ParcelClipper& clipper, bool strictly_inside,
                                 const std::vector<char>& in_chunk) {
  const ParcelClipper::IndexLists lists = clipper.clip(pts);
  std::vector<size_t> first(pts.size(), kNone);
  for (size_t k = 0; k < lists.size(); ++k)
    for (size_t i : lists[k])
      if (first[i] == kNone && (!strictly_inside || clipper.inside(k, pts[i].x(), pts[i].y()))) first[i] = k;
  std::vector<Vec3> out;
  for (size_t k = 0; k < lists.size(); ++k)
    if (in_chunk[k])
      for (size_t i : lists[k])
        if (first[i] == k) out.push_back(pts[i]), first[i] = kNone;
  return out;
}

// Distances to the nearest face, NaN where none: searched around the chunk,
// wider for the points whose nearest face could lie beyond the search.
struct Nearest {
  std::vector<double> roof, wall;
  std::vector<char> of_building;  // wall points within kFootprintReachM of a footprint
  bool roof_faces = false, wall_faces = false;  // any face with an area, anywhere
};

struct ChunkSearch {
  const LoadedInputs& in;
  BatchSink& sink;
  Box points_box;
  double model_reach;
  std::vector<char> loaded;  // per parcel: its model has been searched

  // The parcels not searched yet whose models may reach within r of the chunk's points.
  std::vector<int> new_parcels_within(double r) {
    std::vector<int> ring;
    const Box b = points_box.grown(r);
    for (size_t i = 0; i < in.layer.parcels.size(); ++i)
      if (!loaded[i] && box_of(in.layer.parcels[i].shape).grown(model_reach).touches(b))
        ring.push_back(int(i)), loaded[i] = 1;
    return ring;
  }
};

// Lowers d (the nearest face so far) of the open points by the faces of
// `index`; a point is settled when its nearest face lies within r (no face
// unsearched can be nearer) or nothing is left unsearched. True when all are.
bool settle(const FaceIndex& index, const std::vector<Vec3>& pts, std::vector<double>& d, std::vector<char>& open,
            double r, bool last) {
  std::vector<Vec3> ask;
  std::vector<size_t> at;
  for (size_t k = 0; k < pts.size(); ++k)
    if (open[k]) ask.push_back(pts[k]), at.push_back(k);
  if (ask.empty()) return true;
  std::vector<SurfaceHit> hits;
  if (!index.empty()) hits = index.nearest(ask);
  bool done = true;
  for (size_t j = 0; j < at.size(); ++j) {
    double& best = d[at[j]];
    if (!hits.empty() && !(best <= hits[j].distance)) best = hits[j].distance;  // NaN: none yet
    if (best <= r || last) open[at[j]] = 0;
    else done = false;
  }
  return done;
}

Nearest nearest_faces(ChunkSearch& s, const std::vector<Vec3>& roof, const std::vector<Vec3>& wall) {
  Nearest n;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  n.roof.assign(roof.size(), nan);
  n.wall.assign(wall.size(), nan);
  std::vector<char> roof_open(roof.size(), 1), wall_open(wall.size(), 1);
  s.loaded.assign(s.in.layer.parcels.size(), 0);
  size_t searched = 0;
  for (double r = kFirstSearchM;; r *= 4) {
    const std::vector<int> ring = s.new_parcels_within(r);
    searched += ring.size();
    const bool last = searched == s.in.layer.parcels.size();
    const BatchModel model = s.sink.models(ring);
    if (r == kFirstSearchM)  // every footprint within reach is in the first ring
      n.of_building = near_rings(wall, footprint_rings(model), kFootprintReachM);
    const FaceIndex roofs(world_faces(model, {ElementType::Roof}));
    const FaceIndex walls(world_faces(model, {ElementType::Wall, ElementType::PartyWall}));
    n.roof_faces = n.roof_faces || !roofs.empty();
    n.wall_faces = n.wall_faces || !walls.empty();
    const bool roof_done = settle(roofs, roof, n.roof, roof_open, r, last);
    const bool wall_done = settle(walls, wall, n.wall, wall_open, r, last);
    if ((roof_done && wall_done) || last) return n;
  }
}

}  // namespace

void any_model_deviation(const LoadedInputs& in, const Config& cfg, BatchSink& sink, BatchReport& report) {
  ClipParams exact = cfg.clip;  // inside() reads the parcels as they are
  exact.overhang_buffer_m = 0;
  ClipParams near = cfg.clip;
  near.overhang_buffer_m = kWallPointReachM;
  const ParcelClipper inside(in.layer, exact), reach(in.layer, near);
  std::vector<size_t> all(in.layer.parcels.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = i;
  const double model_reach = cfg.clip.overhang_buffer_m + kOwnershipContextM + kModelMarginM;
  std::vector<Deviation> roof_parts, wall_parts;
  RulerAccumulator roof_ruler, wall_ruler;
  size_t wall_near = 0, measured = 0;
  bool roof_faces = false, wall_faces = false;
  for (const auto& chunk : spatial_chunks(in.layer, all, size_t(cfg.batch.chunk_parcels))) {
    std::vector<char> in_chunk(all.size(), 0);
    for (size_t i : chunk) in_chunk[i] = 1;
    const RegionPoints pts =
        read_region(in.tiles, chunk_box(in.layer, chunk, kWallPointReachM + kRegionMarginM), cfg.classes);
    const std::vector<Vec3> roof = counted_points(pts.roof, inside, true, in_chunk);
    const std::vector<Vec3> wall = counted_points(pts.wall, reach, false, in_chunk);
    ChunkSearch search{in, sink, chunk_box(in.layer, chunk, kWallPointReachM), model_reach, {}};
    const Nearest n = nearest_faces(search, roof, wall);
    roof_faces = roof_faces || n.roof_faces;
    wall_faces = wall_faces || n.wall_faces;
    roof_parts.push_back(deviation(n.roof));
    roof_ruler.add(n.roof);
    wall_parts.push_back(deviation(n.wall));
    std::vector<double> of_buildings;
    for (size_t k = 0; k < wall.size(); ++k)
      if (n.of_building[k]) of_buildings.push_back(n.wall[k]);
    wall_ruler.add(of_buildings);
    wall_near += wall.size();
    measured += of_buildings.size();
  }
  if (roof_faces) report.any_model_roof = pool(roof_parts), report.roof_ruler = roof_ruler.figures();
  if (!wall_faces) return;
  report.any_model_wall = pool(wall_parts);
  report.wall_ruler = wall_ruler.figures();
  if (wall_near > 0) report.wall_points_measured = double(measured) / double(wall_near);
}

}  // namespace c3d
