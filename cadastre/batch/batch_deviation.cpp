#include "cadastre/batch/batch_deviation.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <malloc.h>
#include <unordered_set>

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
// `pts` is freed before the counted ones are copied out, which are sized
// exactly: a chunk's points are the deviation's largest buffers.
std::vector<Vec3> counted_points(std::vector<Vec3>&& pts, const ParcelClipper& clipper, bool strictly_inside,
                                 const std::vector<char>& in_chunk) {
  constexpr uint32_t kNoParcel = std::numeric_limits<uint32_t>::max();
  std::vector<uint32_t> picked;  // indices into pts, in the order counted
  {
    const ParcelClipper::IndexLists lists = clipper.clip(pts);
    std::vector<uint32_t> first(pts.size(), kNoParcel);
    for (size_t k = 0; k < lists.size(); ++k)
      for (size_t i : lists[k])
        if (first[i] == kNoParcel && (!strictly_inside || clipper.inside(k, pts[i].x(), pts[i].y())))
          first[i] = uint32_t(k);
    size_t n = 0;
    for (size_t k = 0; k < lists.size(); ++k)
      if (in_chunk[k])
        for (size_t i : lists[k]) n += first[i] == k;
    picked.reserve(n);
    for (size_t k = 0; k < lists.size(); ++k)
      if (in_chunk[k])
        for (size_t i : lists[k])
          if (first[i] == k) picked.push_back(uint32_t(i)), first[i] = kNoParcel;
  }
  std::vector<Vec3> out(picked.size());
  for (size_t j = 0; j < picked.size(); ++j) out[j] = pts[picked[j]];
  std::vector<Vec3>().swap(pts);
  return out;
}

// Points and their distance to the nearest face so far (NaN: none yet).
struct Measured {
  std::vector<Vec3> pts;
  std::vector<double> d;
  std::vector<char> of_building;  // wall points within kFootprintReachM of a footprint
};

Measured unmeasured(std::vector<Vec3> pts) {
  Measured m;
  m.d.assign(pts.size(), std::numeric_limits<double>::quiet_NaN());
  m.of_building.assign(pts.size(), 0);
  m.pts = std::move(pts);
  return m;
}

// What every chunk's search reads: the parcels' boxes and how far past them
// their models may reach, and the layer's Hilbert order (the chunks are runs
// of it).
struct Layout {
  const ParcelBoxes& boxes;
  double model_reach;
  std::vector<size_t> order;  // the layer's parcels in Hilbert order
  std::vector<size_t> rank;   // each parcel's place in `order`
  size_t page;                // parcels whose models are held at once

  Box reach(size_t parcel) const { return boxes[parcel].grown(model_reach); }
};

Layout layout_of(const ParcelBoxes& boxes, double model_reach, size_t page) {
  Layout l{boxes, model_reach, {}, std::vector<size_t>(boxes.size()), page};
  std::vector<size_t> all(boxes.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = i;
  l.order = hilbert_sorted(boxes, all);
  for (size_t k = 0; k < l.order.size(); ++k) l.rank[l.order[k]] = k;
  return l;
}

// Which points a page of models with this box may hold a nearer face for:
// the open ones whose nearest face so far lies further than the box.
std::vector<char> nearer_than_found(const Measured& m, const std::vector<char>& open, const Box& b) {
  std::vector<char> ask(m.pts.size(), 0);
  for (size_t k = 0; k < m.pts.size(); ++k) {
    if (!open[k]) continue;
    const double dx = std::max({b.min_x - m.pts[k].x(), 0.0, m.pts[k].x() - b.max_x});
    const double dy = std::max({b.min_y - m.pts[k].y(), 0.0, m.pts[k].y() - b.max_y});
    ask[k] = !(m.d[k] <= std::hypot(dx, dy));  // NaN: none found yet
  }
  return ask;
}

// Points asked of a face index at once: their copies and hits (72 bytes a
// point) stay a few MB, however many points a chunk holds.
constexpr size_t kAskedAtOnce = size_t(1) << 16;

// Lowers d (the nearest face so far) of the points `ask` picks to their
// distance to the faces of `index`, kAskedAtOnce at a time.
void lower(const FaceIndex& index, Measured& m, const std::vector<char>& ask) {
  if (index.empty()) return;
  std::vector<Vec3> pts;
  std::vector<size_t> at;
  for (size_t from = 0; from < m.pts.size();) {
    pts.clear(), at.clear();
    for (; from < m.pts.size() && pts.size() < kAskedAtOnce; ++from)
      if (ask[from]) pts.push_back(m.pts[from]), at.push_back(from);
    if (pts.empty()) continue;
    const std::vector<SurfaceHit> hits = index.nearest(pts);
    for (size_t j = 0; j < at.size(); ++j) {
      double& best = m.d[at[j]];
      if (!(best <= hits[j].distance)) best = hits[j].distance;  // NaN: none yet
    }
  }
}

// The roof and wall points of a search, which of them are still open, and
// whether any face was seen.
struct Search {
  Measured roof, wall;
  std::vector<char> roof_open, wall_open;
  bool roof_faces = false, wall_faces = false;  // any face with an area, anywhere
};

// Lowers the open points' distances by the models of `parcels`, read from the
// sink a page of spatially close parcels at a time (so no more than a page of
// models is held, however many parcels are searched); a page is not asked
// about points it cannot hold a nearer face for. With `footprints`, a wall
// point near a page's footprint is marked of_building.
void lower_by_pages(BatchSink& sink, const Layout& l, std::vector<size_t> parcels, Search& s, bool footprints) {
  std::sort(parcels.begin(), parcels.end(), [&](size_t a, size_t b) { return l.rank[a] < l.rank[b]; });
  for (size_t at = 0; at < parcels.size(); at += l.page) {
    const size_t end = std::min(parcels.size(), at + l.page);
    Box box;
    for (size_t k = at; k < end; ++k) box.add(l.reach(parcels[k]));
    const std::vector<char> ask_roof = nearer_than_found(s.roof, s.roof_open, box);
    const std::vector<char> ask_wall = nearer_than_found(s.wall, s.wall_open, box);
    const auto none = [](const std::vector<char>& v) { return std::find(v.begin(), v.end(), 1) == v.end(); };
    if (none(ask_roof) && none(ask_wall) && !footprints) continue;
    const BatchModel model = sink.models(std::vector<int>(parcels.begin() + long(at), parcels.begin() + long(end)));
    if (footprints) {
      const std::vector<char> near = near_rings(s.wall.pts, footprint_rings(model), kFootprintReachM);
      for (size_t k = 0; k < near.size(); ++k) s.wall.of_building[k] |= near[k];
    }
    const FaceIndex roofs(world_faces(model, {ElementType::Roof}));
    const FaceIndex walls(world_faces(model, {ElementType::Wall, ElementType::PartyWall}));
    s.roof_faces = s.roof_faces || !roofs.empty();
    s.wall_faces = s.wall_faces || !walls.empty();
    lower(roofs, s.roof, ask_roof);
    lower(walls, s.wall, ask_wall);
  }
}

// A point is settled when its nearest face lies within r (no face unsearched
// can be nearer) or nothing is left unsearched. True when all are.
bool close_within(const std::vector<double>& d, std::vector<char>& open, double r, bool last) {
  bool done = true;
  for (size_t k = 0; k < d.size(); ++k) {
    if (!open[k]) continue;
    if (d[k] <= r || last) open[k] = 0;
    else done = false;
  }
  return done;
}

// Where the rings stop: a point whose nearest face lies further than this
// from its chunk (one in a parcel with no model, far from any other) waits
// for one pass over all models, instead of its chunk reading most of them.
constexpr double kLastRingM = 160.0;

// A chunk's points against the models around it, in rings growing fourfold
// from kFirstSearchM to kLastRingM; the points left open wait for settle_far.
Search search_rings(BatchSink& sink, const Layout& l, const Box& points_box, std::vector<Vec3> roof,
                    std::vector<Vec3> wall) {
  Search s{unmeasured(std::move(roof)), unmeasured(std::move(wall)), {}, {}};
  s.roof_open.assign(s.roof.pts.size(), 1), s.wall_open.assign(s.wall.pts.size(), 1);
  std::unordered_set<size_t> searched;
  for (double r = kFirstSearchM; r <= kLastRingM; r *= 4) {
    std::vector<size_t> ring;  // the parcels not searched yet whose models may reach within r
    for (size_t i : l.boxes.touching(points_box.grown(r), l.model_reach))
      if (searched.insert(i).second) ring.push_back(i);
    // Every footprint within reach of a point is in the first ring.
    lower_by_pages(sink, l, std::move(ring), s, r == kFirstSearchM);
    const bool last = searched.size() == l.boxes.size();
    const bool roof_done = close_within(s.roof.d, s.roof_open, r, last);
    const bool wall_done = close_within(s.wall.d, s.wall_open, r, last);
    if ((roof_done && wall_done) || last) break;
  }
  return s;
}

// Moves the open points of `from` to `to`; the settled ones stay, in order,
// compacted where they are (a copy of a chunk's points would double the
// deviation's largest buffers).
void move_open(Measured& from, const std::vector<char>& open, Measured& to) {
  size_t kept = 0;
  for (size_t k = 0; k < from.pts.size(); ++k) {
    if (open[k]) {
      to.pts.push_back(from.pts[k]), to.d.push_back(from.d[k]), to.of_building.push_back(from.of_building[k]);
      continue;
    }
    from.pts[kept] = from.pts[k], from.d[kept] = from.d[k], from.of_building[kept] = from.of_building[k];
    ++kept;
  }
  from.pts.resize(kept), from.d.resize(kept), from.of_building.resize(kept);
}

// The batch's pooled figures, a part at a time.
struct Totals {
  std::vector<Deviation> roof_parts, wall_parts;
  RulerAccumulator roof_ruler, wall_ruler;
  size_t wall_near = 0, measured = 0;
  bool roof_faces = false, wall_faces = false;

  void add(const Measured& roof, const Measured& wall) {
    roof_parts.push_back(deviation(roof.d));
    roof_ruler.add(roof.d);
    wall_parts.push_back(deviation(wall.d));
    std::vector<double> of_buildings;
    for (size_t k = 0; k < wall.pts.size(); ++k)
      if (wall.of_building[k]) of_buildings.push_back(wall.d[k]);
    wall_ruler.add(of_buildings);
    wall_near += wall.pts.size();
    measured += of_buildings.size();
  }
};

// How far around its parcels a chunk's points are read.
constexpr double kChunkReachM = kWallPointReachM + kRegionMarginM;

// The points this chunk counts, read from the tiles; the region's other
// points are freed before any model is read. The clippers hold the parcels
// within reach of the region only: every parcel a region point can lie in.
std::pair<std::vector<Vec3>, std::vector<Vec3>> chunk_points(const LoadedInputs& in, const Config& cfg,
                                                             const std::vector<size_t>& chunk) {
  std::vector<char> in_chunk(in.layer.parcels.size(), 0);
  for (size_t i : chunk) in_chunk[i] = 1;
  const Region region = chunk_region(in.boxes, chunk, kChunkReachM);
  ClipParams exact = cfg.clip;  // inside() reads the parcels as they are
  exact.overhang_buffer_m = 0;
  ClipParams near = cfg.clip;
  near.overhang_buffer_m = kWallPointReachM;
  const ParcelClipper inside(in.layer, exact, in.boxes.touching(region.box, 0));
  const ParcelClipper reach(in.layer, near, in.boxes.touching(region.box, kWallPointReachM));
  RegionPoints pts = read_region(in.tiles, region, cfg.classes);
  std::vector<Vec3> roof = counted_points(std::move(pts.roof), inside, true, in_chunk);
  return {std::move(roof), counted_points(std::move(pts.wall), reach, false, in_chunk)};
}

}  // namespace

void any_model_deviation(const LoadedInputs& in, const Config& cfg, BatchSink& sink, BatchReport& report) {
  const double model_reach = cfg.clip.overhang_buffer_m + kOwnershipContextM + kModelMarginM;
  const Layout layout = layout_of(in.boxes, model_reach, size_t(std::max(1, cfg.batch.chunk_parcels)));
  Totals totals;
  Search far;  // the points no ring settled: against every model at the end
  const ChunkLimits limits{layout.page, double(cfg.batch.chunk_points), kChunkReachM};
  for (const std::vector<size_t>& chunk : cut_runs(in.boxes, in.tiles, layout.order, limits)) {
    auto [roof, wall] = chunk_points(in, cfg, chunk);
    Search s = search_rings(sink, layout, chunk_box(in.boxes, chunk, kWallPointReachM), std::move(roof),
                            std::move(wall));
    totals.roof_faces = totals.roof_faces || s.roof_faces;
    totals.wall_faces = totals.wall_faces || s.wall_faces;
    move_open(s.roof, s.roof_open, far.roof);
    move_open(s.wall, s.wall_open, far.wall);
    totals.add(s.roof, s.wall);
    malloc_trim(0);  // the chunk's freed pages back to the system
  }
  if (!far.roof.pts.empty() || !far.wall.pts.empty()) {
    far.roof_open.assign(far.roof.pts.size(), 1), far.wall_open.assign(far.wall.pts.size(), 1);
    lower_by_pages(sink, layout, layout.order, far, false);
    totals.add(far.roof, far.wall);
  }
  if (totals.roof_faces) report.any_model_roof = pool(totals.roof_parts), report.roof_ruler = totals.roof_ruler.figures();
  if (!totals.wall_faces) return;
  report.any_model_wall = pool(totals.wall_parts);
  report.wall_ruler = totals.wall_ruler.figures();
  if (totals.wall_near > 0) report.wall_points_measured = double(totals.measured) / double(totals.wall_near);
}

}  // namespace c3d
