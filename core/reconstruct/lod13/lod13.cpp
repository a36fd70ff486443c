#include "core/reconstruct/lod13/lod13.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <utility>

#include "core/geometry/geometry.h"
#include "core/geometry/polygon_ops.h"
#include "core/log.h"
#include "core/reconstruct/envelope/footprint.h"
#include "core/reconstruct/lod13/layer_solid.h"
#include "core/reconstruct/lod13/layers.h"
#include "core/reconstruct/lod13/raster.h"
#include "core/reconstruct/lod13/regularise.h"
#include "core/reconstruct/measure/measure.h"
#include "core/reconstruct/outline/outline.h"

namespace c3d {
namespace {

using lod13::HeightGrid;
using lod13::Layer;
using lod13::LayerPiece;

// The surface model's cell holds about this many points (the density's own
// resolution: fewer leaves most cells empty, more blurs the steps)...
constexpr double kPointsPerCell = 3;
// ...within these bounds (a finer cell than a UAV roof resolves is noise; a
// coarser one than a metre loses annexes).
constexpr double kMinCellM = 0.25;
constexpr double kMaxCellM = 1.0;
// A layer holds at least this area and this many points at the building's density.
constexpr double kMinLayerAreaM2 = 4;
constexpr double kMinLayerPoints = 40;
// A layer is split while its cells spread more than this (rms, m): half the
// 0.5 m a point may lie from the model before it counts as missed.
constexpr double kLayerToleranceM = 0.3;
// A layer stands at least this far above the one below (a lower step is a
// sloped roof's or a parapet's, not a storey's).
constexpr double kMinStepM = 0.5;
// At most this many layers per building (a lightweight model).
constexpr int kMaxLayers = 16;
// A layer's outline is placed to a cell: its sigma is the uniform spread over one.
constexpr double kCellSigma = 0.2887;  // 1 / sqrt(12)
// Vertices of a layer this close to the outline it stands on are put on it
// (no sliver step walls).
constexpr double kSnapM = 0.02;
// Two layers standing on the same one keep this far apart: touching at a
// corner, they would pinch the shell there (four walls on one vertical edge).
constexpr double kSiblingGapM = 0.1;
// A footprint layer lower than this over the terrain is no building: its
// roof points lie on the ground (bad terrain or bad points), as for the prism.
constexpr double kMinHeightM = 0.1;
// Solids that fail the check are tried again without their smallest layer, this many times.
constexpr int kRetries = 6;

double cell_size(const Polygon2& footprint, size_t points) {
  const double density = double(points) / std::max(area(footprint), 1.0);
  return std::clamp(std::sqrt(kPointsPerCell / std::max(density, 1e-6)), kMinCellM, kMaxCellM);
}

// The IoU of a candidate outline with a layer's cells, counted on the grid.
double raster_iou(const HeightGrid& g, const std::vector<bool>& occupied, const Polygon2& candidate) {
  long both = 0, either = 0;
  for (int i = 0; i < g.nx * g.ny; ++i) {
    const bool in = in_polygon_plan(candidate, g.centre(i)), occ = occupied[size_t(i)];
    both += in && occ;
    either += in || occ;
  }
  return either > 0 ? double(both) / double(either) : 0;
}

// The union of a layer's cells as a polygon (where its points make no outline).
Polygon2 cells_outline(const HeightGrid& g, const std::vector<int>& cells) {
  std::vector<MultiPolygon2> boxes;
  auto corner = [&](int i, int j) { return Vec2(g.origin.x() + i * g.cell, g.origin.y() + j * g.cell); };
  for (int c : cells)  // corners computed alike for neighbours: the boxes share their edges exactly
    boxes.push_back(poly::box(corner(c % g.nx, c / g.nx), corner(c % g.nx + 1, c / g.nx + 1)));
  Polygon2 p = poly::largest(poly::simplify(poly::unite_all(boxes), 0.25 * g.cell));
  p.holes.clear();
  return p;
}

// The roof points of a layer: those over its cells (grown by one cell, so its
// edge is where its points end) no lower than its lowest cell.
std::vector<Vec2> layer_points(const HeightGrid& g, const Layer& l, const std::vector<Vec3>& points) {
  std::vector<bool> near(g.z.size(), false);
  double low = 1e300;
  for (int c : l.cells) {
    low = std::min(low, g.z[size_t(c)]);
    near[size_t(c)] = true;
    for (int n : lod13::neighbours8(g.nx, g.ny, c)) near[size_t(n)] = true;
  }
  std::vector<Vec2> out;
  for (const auto& p : points) {
    const int c = g.cell_of(p.head<2>());
    if (c >= 0 && near[size_t(c)] && p.z() >= low) out.push_back(p.head<2>());
  }
  return out;
}

// Vertices within kSnapM of the outline below go onto it.
Polygon2 snapped_to(Polygon2 p, const Polygon2& below) {
  const std::vector<lod13::Segment> edges = lod13::segments_of(below.outer);
  for (auto& v : p.outer)
    for (const auto& e : edges) {
      const Vec2 d = e.b - e.a;
      const double t = std::clamp(d.dot(v - e.a) / d.squaredNorm(), 0.0, 1.0);
      const Vec2 q = (v - e.a).norm() < kSnapM ? e.a : (v - e.b).norm() < kSnapM ? e.b : e.a + t * d;
      if ((q - v).norm() < kSnapM) {
        v = q;
        break;
      }
    }
  return p;
}

// The layer grown over the strips of the layer below that it leaves narrower
// than `width` (a cell: nothing the points resolve), so that a wall nearly
// flush with the one below is flush, not a sliver of roof between two walls.
MultiPolygon2 flush_with(const MultiPolygon2& layer, const Polygon2& below, double width) {
  const MultiPolygon2 rest = poly::subtract({below}, layer);
  const MultiPolygon2 thin = poly::subtract(rest, poly::buffer(poly::buffer(rest, -0.5 * width), 0.5 * width));
  return {poly::largest(poly::intersect(poly::unite(layer, thin), {below}))};
}

struct Outlines {
  std::vector<LayerPiece> pieces;  // per layer kept
  std::vector<int> layer;          // the tree's layer of each piece
  Lod13Summary summary;
};

// The layer's outline: from its points, made regular against its cells and
// the outline below, inside that outline and clear of its earlier siblings.
Polygon2 layer_outline(const HeightGrid& g, const std::vector<Layer>& layers, size_t k, const Polygon2& below,
                       const MultiPolygon2& siblings, const PrismInput& in, const std::vector<Vec3>& points,
                       Lod13Summary& sum) {
  OutlineOptions oo;
  oo.spacing = in.spacing;
  std::vector<bool> occupied(g.z.size(), false);
  for (int c : layers[k].cells) occupied[size_t(c)] = true;
  lod13::RegulariseInput ri;
  ri.iou = [&](const Polygon2& p) { return raster_iou(g, occupied, p); };
  ri.outline = roof_outline(layer_points(g, layers[k], points), oo);
  if (ri.outline.outer.size() < 3 || ri.iou(ri.outline) < lod13::kMinIou)  // too few points for an outline
    ri.outline = cells_outline(g, layers[k].cells);
  ri.axis = dominant_direction(in.footprint.outer);
  ri.below = lod13::segments_of(below.outer);
  ri.align_m = ri.min_edge_m = std::max(g.cell, 2 * in.spacing);
  const lod13::Regularised r = lod13::regularise(ri);
  std::string kept;
  for (const auto& step : r.steps) kept += (kept.empty() ? "" : ", ") + step;
  log::debug(in.building_id + " layer " + std::to_string(k) + ": IoU " + std::to_string(r.iou_found) + " as found, " +
             std::to_string(r.iou) + " regular (" + kept + ")");
  sum.iou_found.push_back(r.iou_found);
  sum.iou.push_back(r.iou);
  MultiPolygon2 inside = flush_with(poly::intersect({snapped_to(r.outline, below)}, {below}), below, g.cell);
  if (!siblings.empty()) inside = poly::subtract(inside, poly::buffer(siblings, kSiblingGapM));
  Polygon2 p = poly::largest(poly::simplify(inside, 1e-3));
  p.holes.clear();
  return envelope::without_specks(p);
}

// The layers' outlines, parents first; a layer whose outline comes to less
// than the least layer area, or whose top (a median) lies less than a step
// above its parent's, goes, and its children stand on its parent.
Outlines outlines_of(const HeightGrid& g, const std::vector<Layer>& layers, const PrismInput& in,
                     const std::vector<Vec3>& points, double min_area) {
  Outlines out;
  std::vector<int> piece_of(layers.size(), -1), stands_on(layers.size(), -1);
  for (size_t k = 0; k < layers.size(); ++k) {
    const int parent = k == 0 ? -1 : stands_on[k] >= 0 ? stands_on[k] : layers[k].parent;
    Polygon2 outline = in.footprint;
    if (k > 0) {
      MultiPolygon2 siblings;  // the outlines already standing on the same layer
      for (size_t j = 1; j < k; ++j)
        if (piece_of[j] >= 0 && (stands_on[j] >= 0 ? stands_on[j] : layers[j].parent) == parent)
          siblings.push_back(out.pieces[size_t(piece_of[j])].outline);
      outline = layer_outline(g, layers, k, out.pieces[size_t(piece_of[size_t(parent)])].outline, siblings, in,
                              points, out.summary);
    }
    const bool no_step = k > 0 && layers[k].z - layers[size_t(parent)].z < kMinStepM;
    if (k > 0 && (no_step || outline.outer.size() < 3 || area(outline) < min_area)) {
      for (size_t j = k + 1; j < layers.size(); ++j)
        if (layers[j].parent == int(k)) stands_on[j] = parent;
      continue;
    }
    piece_of[k] = int(out.pieces.size());
    out.pieces.push_back({outline, layers[k].z});
    out.layer.push_back(int(k));
  }
  return out;
}

// Per piece, the building's roof points over it (the highest piece holding
// each) and their rms about its top.
struct PieceSupport {
  std::vector<int> points;
  std::vector<double> rms;
  double rms_all = 0;
};

PieceSupport support_of(const std::vector<LayerPiece>& pieces, const std::vector<Vec3>& points) {
  PieceSupport s;
  s.points.assign(pieces.size(), 0);
  std::vector<double> sum2(pieces.size(), 0);
  double all = 0;
  long n = 0;
  for (const auto& p : points)
    for (size_t k = pieces.size(); k-- > 0;)
      if (in_polygon_plan(pieces[k].outline, p.head<2>())) {
        const double d2 = (p.z() - pieces[k].z) * (p.z() - pieces[k].z);
        ++s.points[k], sum2[k] += d2, all += d2, ++n;
        break;
      }
  for (size_t k = 0; k < pieces.size(); ++k) s.rms.push_back(s.points[k] ? std::sqrt(sum2[k] / s.points[k]) : 0);
  s.rms_all = n ? std::sqrt(all / double(n)) : 0;
  return s;
}

// One wall element as the prism's: its area known to its top (the roof points
// spread about the layers' tops) and to its ends (an outer wall stands within
// an overhang of the outline, a step where the cells end).
Element wall_element(const lod13::StackedSolid::Wall& w, double sigma_top, double sigma_line) {
  Element e;
  e.type = w.party ? ElementType::PartyWall : ElementType::Wall;
  e.evidence = w.party ? WallEvidence::ParcelBoundary : w.outer ? WallEvidence::None : WallEvidence::RoofStep;
  const double len = (w.face.ring[1] - w.face.ring[0]).norm();
  double top = w.face.ring[0].z();
  for (const auto& v : w.face.ring) top = std::max(top, v.z());
  const double height = top - w.face.ring[0].z();
  e.faces.push_back(w.face);
  measure_element(e);
  e.sigma_area = std::hypot(len * sigma_top, height * sigma_line);
  return e;
}

// The building of the stacked solid: a roof element per layer, a wall per
// wall face, the ground; measured and checked.
Building assemble(const lod13::StackedSolid& s, const std::vector<LayerPiece>& pieces, const PrismInput& in,
                  const std::vector<Vec3>& points, double terrain_z, double cell) {
  Building b;
  b.id = in.building_id;
  b.lod = Lod::Lod13;
  b.terrain_z = terrain_z;
  const PieceSupport sup = support_of(pieces, points);
  for (size_t k = 0; k < pieces.size(); ++k) {
    Element roof;
    roof.type = ElementType::Roof;
    for (size_t f = 0; f < s.roofs.size(); ++f)
      if (s.roof_layer[f] == int(k)) roof.faces.push_back(s.roofs[f]);
    if (roof.faces.empty()) continue;
    roof.support_points = sup.points[k];
    roof.rmse = sup.rms[k];
    measure_element(roof, kCellSigma * cell);
    b.elements.push_back(std::move(roof));
  }
  for (const auto& w : s.walls)
    b.elements.push_back(wall_element(w, sup.rms_all, w.outer ? in.default_overhang : kCellSigma * cell));
  Element ground;
  ground.type = ElementType::Ground;
  ground.faces = {s.ground};
  measure_element(ground, in.default_overhang);
  b.elements.push_back(std::move(ground));
  b.solid = lod13::shell_of(s);
  measure_building(b, in.storey_height);
  return b;
}

Building without_layers(const std::string& id, const std::string& why) {
  Building b;
  b.id = id;
  b.lod = Lod::Lod13;
  b.solid_valid = false;
  b.solid_problem = why;
  return b;
}

// The index of the smallest piece but the footprint.
size_t smallest_layer(const std::vector<LayerPiece>& pieces) {
  size_t best = 1;
  for (size_t k = 2; k < pieces.size(); ++k)
    if (area(pieces[k].outline) < area(pieces[best].outline)) best = k;
  return best;
}

}  // namespace

Building lod13_layers(const PrismInput& in, const std::vector<Vec3>& roof_points,
                      const std::function<std::string(const Building&)>& face_defect, Lod13Summary* summary) {
  if (in.footprint.outer.size() < 3) return without_layers(in.building_id, "no valid footprint");
  if (roof_points.empty()) return without_layers(in.building_id, "no roof points");
  double terrain_z = 0;
  try {
    terrain_z = envelope::mean_terrain(in.footprint, in.terrain);
  } catch (const std::runtime_error& e) {
    return without_layers(in.building_id, e.what());
  }
  const double cell = cell_size(in.footprint, roof_points.size());
  const HeightGrid g = lod13::height_grid(in.footprint, roof_points, cell);
  lod13::LayerOptions lo;
  lo.min_area_m2 = std::max(kMinLayerAreaM2, kMinLayerPoints * area(in.footprint) / double(roof_points.size()));
  lo.tolerance_m = kLayerToleranceM;
  lo.min_step_m = kMinStepM;
  lo.max_layers = kMaxLayers;
  const std::vector<Layer> layers = lod13::layer_tree(g, lo);
  if (layers.empty()) return without_layers(in.building_id, "no cell of the footprint");
  if (!(layers[0].z - terrain_z >= kMinHeightM)) return without_layers(in.building_id, "the roof points lie at the terrain");
  Outlines o = outlines_of(g, layers, in, roof_points, lo.min_area_m2);
  o.summary.cell = cell;
  Building b;
  for (int attempt = 0; attempt <= kRetries; ++attempt) {
    const lod13::StackedSolid s = lod13::stacked_solid(o.pieces, terrain_z, in.party_edge);
    b = s.problem.empty() ? assemble(s, o.pieces, in, roof_points, terrain_z, cell)
                          : without_layers(in.building_id, s.problem);
    const std::string defect = b.solid_valid && face_defect ? face_defect(b) : "";
    if (!defect.empty()) b.solid_valid = false, b.solid_problem = defect;
    log::debug(in.building_id + ": LoD 1.3 of " + std::to_string(o.pieces.size()) + " layers: " +
               (b.solid_valid ? "valid" : b.solid_problem));
    if (b.solid_valid || o.pieces.size() < 2) break;
    o.pieces.erase(o.pieces.begin() + long(smallest_layer(o.pieces)));
  }
  o.summary.layers = int(o.pieces.size());
  o.summary.heights.clear();
  for (const auto& p : o.pieces) o.summary.heights.push_back(p.z - terrain_z);
  char note[96];
  std::snprintf(note, sizeof note, "LoD 1.3 of %d height layer%s", o.summary.layers, o.summary.layers == 1 ? "" : "s");
  if (b.solid_valid) b.lod_note = note;
  if (summary) *summary = o.summary;
  return b;
}

void adopt_lod13(Building& b, Building layered) {
  layered.lod_note = "LoD 2.2 invalid (" + b.solid_problem + "): " + layered.lod_note;
  b = std::move(layered);
}

}  // namespace c3d
