#include "core/reconstruct/reconstruct.h"

#include "core/cpu_clock.h"

#include <algorithm>
#include <ctime>
#include <cstdio>
#include <deque>
#include <map>
#include <functional>
#include <mutex>
#include <set>
#include <string>
#include <utility>

#include "core/check/polygon_rules.h"
#include "core/check/solid_check.h"
#include "core/evaluate/evaluate.h"
#include "core/geometry/geometry.h"
#include "core/geometry/polygon_ops.h"
#include "core/log.h"
#include "core/optimizer/optimizer.h"
#include "core/optimizer/refine_curved.h"
#include "core/reconstruct/building_plan.h"
#include "core/reconstruct/curved_roofs.h"
#include "core/reconstruct/envelope/envelope.h"
#include "core/reconstruct/lod12/lod12.h"
#include "core/reconstruct/lod13/lod13.h"
#include "core/reconstruct/lower_lods.h"
#include "core/reconstruct/measure/measure.h"
#include "core/reconstruct/ownership/ownership.h"
#include "core/reconstruct/roof/roof.h"
#include "core/reconstruct/segment/segmentation.h"

namespace c3d {
namespace {

// The roof partition's cell follows the point spacing, within these bounds
// (unless the configuration fixes it): finer than the points resolve is noise,
// coarser blurs the lines between planes.
constexpr double kPartitionCellSpacings = 1.5;
constexpr double kMinPartitionCellM = 0.1;
constexpr double kMaxPartitionCellM = 0.25;


class StageClock {
 public:
  explicit StageClock(std::vector<Timing>& out) : out_(out) {}
  void lap(const std::string& stage) {
    const double now = thread_cpu_seconds();
    const double s = now - last_;
    last_ = now;
    for (auto& t : out_)
      if (t.stage == stage) {
        t.seconds += s;
        return;
      }
    out_.push_back({stage, s});
  }

 private:
  std::vector<Timing>& out_;
  double last_ = thread_cpu_seconds();
};

Vec2 plan(const Vec3& p) { return p.head<2>(); }

// What every step of modelling a parcel's buildings reads: the scene, the
// roofs this parcel models (planes fitted to the points it keeps), who owns
// what at the boundary, the parameters; and the clock the steps lap.
struct ParcelContext {
  const ParcelScene& scene;
  const Segmentation& roofs;
  const Ownership& own;
  const ReconstructionParams& p;
  StageClock& clock;
};

// Why a building's faces would fail validation ("" when they pass): the ring
// and polygon rules `validate` applies, with its tolerances, to the faces as
// computed, as the CityJSON export writes them (a thin triangle can tilt
// there) and as val3dity reads them back (vertices within 1 mm merged).
std::string face_defect(const Building& b) {
  const PolygonRules rules;  // validate's defaults
  std::vector<Face> all;
  std::vector<ElementType> type;
  for (const auto& e : b.elements)
    for (const auto& face : e.faces) all.push_back(face), type.push_back(e.type);
  std::vector<Face> exported;
  for (const Face& f : all) exported.push_back(on_export_grid(f));
  std::vector<Face> snapped = snapped_together(exported, rules.snap_tol);
  for (const std::vector<Face>* faces : {&all, &exported, &snapped})
    for (size_t i = 0; i < faces->size(); ++i) {
      if (faces == &snapped && snapped[i].ring == exported[i].ring && snapped[i].holes == exported[i].holes)
        continue;  // no vertex merged: checked as exported
      VertexSnap snap(rules.snap_tol);
      std::vector<std::vector<int>> rings;
      std::vector<PolygonIssue> issues;
      if (!check_polygon((*faces)[i], rules, snap, rings, issues))
        return std::string("a ") + to_string(type[i]) + " face" + issues.front().where + ": " +
               issues.front().message;
    }
  return "";
}

// Why a refined building is unusable ("" when it is fine): faces as above,
// the shell still closed, manifold, outward and free of self-intersections.
std::string refinement_defect(const Building& b) {
  const std::string faces = face_defect(b);
  if (!faces.empty()) return faces;
  const SolidCheck check = check_solid(b.solid);
  return check.ok ? "" : check.summary();
}

// The segmentation as this parcel models it: what ownership keeps, each
// plane fitted again to the points kept of it (a split roof's to its part).
Segmentation modelled_roofs(const ParcelScene& s, const Segmentation& seg, const Ownership& own,
                            const ReconstructionParams& p) {
  Segmentation kept = kept_segmentation(seg, own);
  for (auto& c : kept.components)
    if (int(c.points.size()) >= p.min_component_points)
      c.fit = fit_plane_robust(s.roof_points, c.points, p.plane_inlier_m);
  return kept;
}

std::set<int> roofs_of(const Segmentation& seg, const std::vector<int>& components) {
  std::set<int> roofs;
  for (int c : components) roofs.insert(seg.components[size_t(c)].roof);
  return roofs;
}

// The roof points the partition of building `bp` sorts into its planes' regions.
RoofPartitionInput roof_partition_input(const ParcelContext& c, const BuildingPlan& bp) {
  const Segmentation& seg = c.roofs;
  RoofPartitionInput rp;
  rp.outline = bp.outline;  // add_points_by_height keeps the points inside it
  rp.components = bp.components;
  for (int k : bp.components) {  // one a neighbour's cut left in two buildings serves both, with one plane
    rp.planes.push_back(seg.components[k].fit.plane);
    for (int i : seg.components[k].points) {
      rp.points.push_back(plan(c.scene.roof_points[i]));
      rp.labels.push_back(k);
    }
  }
  const std::set<int> roofs = roofs_of(seg, bp.components);
  std::vector<Vec3> untaken;  // this building's roof points no plane took
  for (size_t i = 0; i < c.scene.roof_points.size(); ++i)
    if (seg.label[i] < 0 && roofs.count(seg.roof_of[i])) untaken.push_back(c.scene.roof_points[i]);
  add_points_by_height(rp, untaken);
  rp.cell = c.p.partition_cell_m > 0
                ? c.p.partition_cell_m
                : std::max(kMinPartitionCellM, std::min(kMaxPartitionCellM, kPartitionCellSpacings * seg.spacing));
  return rp;
}

// The roof partition over `outline`: the outline split where a neighbour's
// roof ends, the planes' regions over it and its party edges, into `ei`.
void partition_over(const Polygon2& outline, const RoofPartitionInput& points, const ParcelContext& c,
                    EnvelopeInput& ei) {
  RoofPartitionInput rp = points;
  rp.outline = ei.outline = split_where_neighbour_roof_ends(outline, c.own);
  ei.roof = partition_roof(rp);
  ei.fits.clear();
  for (const auto& r : ei.roof) ei.fits.push_back(c.roofs.components[r.component].fit);
  ei.party_edge = find_party_edges(ei.outline, c.own);
  c.clock.lap("roof partition");
}

// `b` refined by the optimizer on the building's own roof points, or `b`
// itself where the refinement would cost a valid solid.
Building refined_or_kept(Building b, const ParcelContext& c, const BuildingPlan& bp) {
  std::vector<Vec3> own;
  for (int k : bp.components)
    for (int i : c.roofs.components[k].points) own.push_back(c.scene.roof_points[i]);
  OptimizerOptions o;
  o.device = parse_compute_device(c.p.optimize_device);
  Building refined = b;
  OptimizeReport rep = optimize_building(refined, own, o);
  static std::once_flag logged;
  std::call_once(logged, [&] { log::info("optimizer: " + rep.device); });
  const std::string why = refinement_defect(refined);
  if (why.empty()) return refined;
  log::warn("optimizer: " + b.id + " kept unrefined (" + why + ")");  // keep the reconstruction
  return b;
}

struct ModelledBuilding {
  Building building;
  FootprintApart apart;  // the footprint's parts where it came apart under the roof
};

// Models building `bp`: grown under a neighbour's eave and onto walls seen
// outside it, its roof partitioned, its envelope built, refined, measured.
ModelledBuilding model_building(const ParcelContext& c, const BuildingPlan& bp, const std::string& id) {
  const RoofPartitionInput rp = roof_partition_input(c, bp);
  EnvelopeInput ei;
  ei.building_id = id;
  c.clock.lap("roof partition input");
  partition_over(grow_under_neighbour_eaves(bp.outline, c.own, roofs_of(c.roofs, bp.components), bp.room), rp, c, ei);
  ei.wall_points = c.scene.wall_points;
  ei.roof_points = c.scene.roof_points;
  ei.terrain = c.scene.terrain;
  ei.default_overhang = c.p.default_overhang_m;
  ei.storey_height = c.p.storey_height_m;
  ei.spacing = c.roofs.spacing;
  GrownOutline grown = grow_to_walls_outside(ei, bp.room);
  if (!grown.walls.empty()) {  // a wall seen outside: the floor and the roof reach it
    partition_over(poly::largest(poly::drop_needles({grown.outline}, kNeedleAngle)), rp, c, ei);
    ei.walls_on_outline = std::move(grown.walls);
  }
  ModelledBuilding m;
  m.building = build_building(ei, &m.apart);
  c.clock.lap("envelope");
  if (c.p.optimize) m.building = refined_or_kept(std::move(m.building), c, bp);
  measure_building(m.building, c.p.storey_height_m);
  c.clock.lap("measure");
  return m;
}

// What the model leaves out of a building whose footprint came apart and
// could not be cut into its houses.
std::string apart_note(const FootprintApart& apart) {
  double all = 0;
  for (const auto& part : apart.parts) all += area(part);
  char note[160];
  std::snprintf(note, sizeof note, "the footprint comes apart under the roof; only its largest part "
                "(%.1f of %.1f m^2) has walls and a floor", area(apart.parts.front()), all);
  return note;
}

struct ModelledParcel {
  std::vector<Building> buildings;
  std::vector<BuildingPlan> plans;  // each building's, in step
  std::string notes;                // what the models leave out
};

// Models the plans on the work list front to back. A plan whose footprint
// comes apart under its roof is replaced by its houses, at the front of the
// list: they are modelled next, and may come apart in turn.
ModelledParcel model_work_list(const ParcelContext& c, std::deque<BuildingPlan> todo) {
  ModelledParcel m;
  while (!todo.empty()) {
    const BuildingPlan bp = std::move(todo.front());
    todo.pop_front();
    const std::string id = c.scene.parcel_id + "_b" + std::to_string(m.buildings.size() + 1);
    ModelledBuilding mb = model_building(c, bp, id);
    const std::vector<BuildingPlan> houses = houses_under(bp, mb.apart);
    if (!houses.empty()) {  // one building per house, modelled next
      todo.insert(todo.begin(), houses.begin(), houses.end());
      continue;
    }
    if (mb.apart.parts.size() > 1)  // no cut found: say what the model leaves out
      m.notes += (m.notes.empty() ? "" : "; ") + id + ": " + apart_note(mb.apart);
    m.buildings.push_back(std::move(mb.building));
    m.plans.push_back(bp);
  }
  return m;
}

// A building whose solid or faces fail is modelled again from outlines on the
// hull's own axes: turning the axes moves edges by millimetres, and where four
// planes meet that can make the difference between one clean vertex and a
// sliver. The second model is kept only if it passes.
void remodel_defective(const ParcelContext& c, ModelledParcel& m) {
  std::vector<BuildingPlan> fallback;
  for (size_t k = 0; k < m.buildings.size(); ++k) {
    Building& b = m.buildings[k];
    const BuildingPlan& first = m.plans[k];
    if (b.solid_valid && face_defect(b).empty()) continue;
    if (fallback.empty()) fallback = plan_buildings(c.scene, c.roofs, c.own.cut, c.p.loose_point_reach_m, false);
    for (const auto& bp : fallback) {
      const double common = area(poly::intersect({bp.outline}, {first.outline}));
      if (bp.components != first.components ||  // a roof cut in parts: the part here
          common < 0.5 * area(first.outline) || common < 0.5 * area(bp.outline))
        continue;
      Building again = model_building(c, bp, b.id).building;
      if (again.solid_valid && face_defect(again).empty()) b = std::move(again);
      break;
    }
    const std::string faces = face_defect(b);
    if (b.solid_valid && !faces.empty()) {  // closed, but `validate` would reject it: say so
      b.solid_valid = false;
      b.solid_problem = faces;
    }
  }
}

// Building `bp`'s own roof points: its planes' points and the points of its
// roofs no plane took that lie inside `footprint`.
std::vector<Vec3> own_roof_points(const ParcelContext& c, const BuildingPlan& bp, const Polygon2& footprint) {
  std::vector<Vec3> pts;
  for (int k : bp.components)
    for (int i : c.roofs.components[size_t(k)].points) pts.push_back(c.scene.roof_points[size_t(i)]);
  const std::set<int> roofs = roofs_of(c.roofs, bp.components);
  const MultiPolygon2 inside{footprint};
  for (size_t i = 0; i < c.scene.roof_points.size(); ++i)
    if (c.roofs.label[i] < 0 && roofs.count(c.roofs.roof_of[i]) && poly::covers(inside, plan(c.scene.roof_points[i])))
      pts.push_back(c.scene.roof_points[i]);
  return pts;
}

// What the prism and the layers of plan `bp` are built from (see lod12.h):
// the footprint, with or without its holes, and the building's own roof
// points over it.
// With `over_footprint`, only the points over the footprint (over_footprint
// in lower_lods.h: a plane two houses share gives each the other's points).
struct PrismSource {
  PrismInput in;
  std::vector<Vec3> own;
  bool over_footprint = false;
};

PrismSource prism_source(const ParcelContext& c, const BuildingPlan& bp, const std::string& id, bool holes,
                         bool over_footprint = false) {
  PrismSource s;
  s.over_footprint = over_footprint;
  PrismInput& in = s.in;
  in.building_id = id;
  in.footprint = prism_footprint(bp.outline, holes);
  if (in.footprint.outer.size() >= 3) in.party_edge = find_party_edges(in.footprint, c.own);
  s.own = own_roof_points(c, bp, in.footprint);
  if (over_footprint) s.own = c3d::over_footprint(s.own, in.footprint);
  for (const auto& q : s.own) in.roof_heights.push_back(q.z());
  in.terrain = c.scene.terrain;
  in.spacing = c.roofs.spacing;
  in.default_overhang = c.p.default_overhang_m;
  in.storey_height = c.p.storey_height_m;
  return s;
}

// A model of plan `bp` from `with_holes` (prism_source with its holes) and
// why it fails ("" when it passes check_solid and the face rules); a
// courtyard's model that fails is tried again without its holes.
using LodModel = std::function<Building(const PrismSource&)>;
std::pair<Building, std::string> valid_model(const ParcelContext& c, const BuildingPlan& bp,
                                             const PrismSource& with_holes, const LodModel& model) {
  std::pair<Building, std::string> out;
  out.first = model(with_holes);
  out.second = out.first.solid_valid ? face_defect(out.first) : out.first.solid_problem;
  if (out.second.empty() || with_holes.in.footprint.holes.empty()) return out;
  out.first = model(prism_source(c, bp, with_holes.in.building_id, false, with_holes.over_footprint));
  out.second = out.first.solid_valid ? face_defect(out.first) : out.first.solid_problem;
  return out;
}

// The LoD 1.2 prism of plan `bp` (see lod12.h) and why it fails, as valid_model.
std::pair<Building, std::string> lod12_of(const ParcelContext& c, const BuildingPlan& bp, const PrismSource& src) {
  return valid_model(c, bp, src, [](const PrismSource& s) { return lod12_prism(s.in); });
}

// The LoD 1.3 of plan `bp` (see lod13/lod13.h) and why it fails, as valid_model.
std::pair<Building, std::string> lod13_of(const ParcelContext& c, const BuildingPlan& bp, const PrismSource& src) {
  return valid_model(c, bp, src, [](const PrismSource& s) { return lod13_layers(s.in, s.own, face_defect); });
}

// A building whose LoD 2.2 model is still invalid after remodel_defective
// becomes its LoD 1.3 layers where those are valid, else its LoD 1.2 prism
// where that is valid, and says so; where even the prism fails it stays as it
// is, invalid, and says that too.
void fall_back_to_lower_lod(const ParcelContext& c, ModelledParcel& m) {
  bool tried = false;
  for (size_t k = 0; k < m.buildings.size(); ++k) {
    Building& b = m.buildings[k];
    if (b.solid_valid) continue;  // remodel_defective marked face defects invalid
    tried = true;
    const PrismSource src = prism_source(c, m.plans[k], b.id, true);
    auto [layered, why13] = lod13_of(c, m.plans[k], src);
    if (why13.empty()) {
      adopt_lod13(b, std::move(layered));
    } else {
      auto [prism, why] = lod12_of(c, m.plans[k], src);
      adopt_prism(b, std::move(prism), why);
      b.lod_note += "; no valid LoD 1.3 (" + why13 + ")";
    }
    log::info(b.id + ": " + b.lod_note);
  }
  if (tried) c.clock.lap("lod 1.3 / 1.2");
}

// Every modelled building's attributes from its own roof points over its
// footprint (an LoD 2.2 model's ground, else its plan's outline) and its
// valid lower LoDs on that footprint, from the same points: a 2.2 model gets its LoD
// 1.2 prism and 1.3 layers, a 1.3 fallback its prism.
void describe_buildings(const ParcelContext& c, ModelledParcel& m) {
  const double min_density = min_good_density(c.p.min_component_area_m2);
  for (size_t k = 0; k < m.buildings.size(); ++k) {
    Building& b = m.buildings[k];
    BuildingPlan bp = m.plans[k];
    if (b.lod == Lod::Lod22) {  // the lower LoDs stand where its walls stand, as 3DBAG's share one footprint
      const Polygon2 ground = ground_footprint(b);
      if (ground.outer.size() >= 3) bp.outline = ground;
    }
    const PrismSource src = prism_source(c, bp, b.id, true, true);
    const std::vector<Vec3>& own = src.own;
    std::vector<PlaneFit> planes;
    for (int i : bp.components)
      if (c.roofs.components[size_t(i)].fit.inliers > 0) planes.push_back(c.roofs.components[size_t(i)].fit);
    const double over = src.in.footprint.outer.size() >= 3 ? area(src.in.footprint) : totals(b).roof_plan;
    b.attributes = roof_attributes(b, own, planes, over, min_density);
    if (b.lod == Lod::Lod12) continue;
    auto [prism, why12] = lod12_of(c, bp, src);
    if (why12.empty()) b.lower_lods.push_back(lod_shell_of(prism, own));
    else log::debug(b.id + ": no LoD 1.2 below its " + to_string(b.lod) + " (" + why12 + ")");
    if (b.lod != Lod::Lod22) continue;
    auto [layered, why13] = lod13_of(c, bp, src);
    if (why13.empty()) b.lower_lods.push_back(lod_shell_of(layered, own));
    else log::debug(b.id + ": no LoD 1.3 below its 2.2 (" + why13 + ")");
  }
  c.clock.lap("lower lods");
}

// A building with no valid model at any LoD is not reported as modelled (no
// invalid solid is ever `ok`): it leaves the parcel, and the notes say why.
// Returns how many left.
int drop_unmodellable(ModelledParcel& m) {
  int dropped = 0;
  for (size_t k = 0; k < m.buildings.size();) {
    const Building& b = m.buildings[k];
    if (b.solid_valid) {
      ++k;
      continue;
    }
    m.notes += (m.notes.empty() ? "" : "; ") + b.id + ": no valid model (" + b.solid_problem + ")" +
               (b.lod_note.empty() ? "" : "; " + b.lod_note);
    m.buildings.erase(m.buildings.begin() + long(k));
    m.plans.erase(m.plans.begin() + long(k));
    ++dropped;
  }
  return dropped;
}

// What the parcel's reason says of a building: its LoD 1.3 / 1.2 and why ("" for an
// LoD 2.2 model). Every building here is valid: drop_unmodellable took the rest.
std::string building_reason(const Building& b) {
  return b.lod_note.empty() ? "" : b.id + ": " + b.lod_note;
}

// Deviations of the buildings from the parcel's own roof points and the wall
// points near it.
void evaluate_on_parcel(const ParcelScene& s, std::vector<Building>& buildings) {
  std::vector<Vec3> inside_roof;
  for (const auto& q : s.roof_points)
    if (poly::covers(s.parcel, plan(q))) inside_roof.push_back(q);
  std::vector<Vec3> near_wall;  // by distance: a mitred buffer reaches further at corners
  for (const auto& q : s.wall_points)
    if (poly::distance(s.parcel, plan(q)) <= kWallPointReachM) near_wall.push_back(q);
  evaluate_buildings(buildings, inside_roof, near_wall);
}

// Buildings whose roof is one curved surface modelled on it; what the parcel's
// reason says of curved surfaces the planar models stand for ("" for none).
std::string curved_roofs(const ParcelContext& c, ModelledParcel& m) {
  std::string note;
  for (size_t k = 0; k < m.buildings.size(); ++k) {
    Building& b = m.buildings[k];
    // All its roof's points: a curved roof's planar footprint may fall short of its rim.
    const std::vector<Vec3> own = prism_source(c, m.plans[k], b.id, true, false).own;
    const std::string why = model_curved_roof(b, own, c.scene.roof_points, c.scene.wall_points, c.roofs.spacing,
                                              c.p.storey_height_m);
    if (!why.empty()) note += (note.empty() ? "" : "; ") + why;
  }
  c.clock.lap("curved surfaces");
  return note;
}

// Seed 000's optimizer on the curved buildings (on by default): each one's
// dense mesh snapped onto its exact surfaces, and what that did.
void refine_curved_buildings(const ParcelContext& c, std::vector<Building>& buildings) {
  if (!c.p.refine_curved) return;
  std::vector<Vec3> points = c.scene.roof_points;
  points.insert(points.end(), c.scene.wall_points.begin(), c.scene.wall_points.end());
  for (Building& b : buildings)
    if (!b.exact.parts.empty())
      b.refinement = refine_curved(b, points, c.roofs.spacing, parse_compute_device(c.p.optimize_device)).effect;
  c.clock.lap("refine curved");
}

}  // namespace

ParcelResult reconstruct_parcel(const ParcelScene& s, const ReconstructionParams& p) {
  ParcelResult r;
  r.parcel_index = s.parcel_index;
  r.parcel_id = s.parcel_id;
  r.roof_points = long(s.roof_points.size());
  r.wall_points = long(s.wall_points.size());
  StageClock clock(r.timings);
  try {
    if (s.roof_points.size() < size_t(p.min_component_points)) {
      r.status = ParcelStatus::Empty;
      r.reason = s.roof_points.empty() ? "no roof points in the parcel"
                                       : "too few roof points for a building (" +
                                             std::to_string(s.roof_points.size()) + ")";
      return r;
    }
    const Segmentation seg = segment_roofs(s.roof_points, p, s.terrain);
    clock.lap("segment");
    const Ownership own = decide_ownership(s, seg, p);
    const Segmentation roofs = modelled_roofs(s, seg, own, p);
    clock.lap("ownership");
    const ParcelContext c{s, roofs, own, p, clock};
    const std::vector<BuildingPlan> plans = plan_buildings(s, roofs, own.cut, p.loose_point_reach_m, true);
    clock.lap("boundary");
    ModelledParcel m = model_work_list(c, std::deque<BuildingPlan>(plans.begin(), plans.end()));
    remodel_defective(c, m);
    fall_back_to_lower_lod(c, m);
    const int dropped = drop_unmodellable(m);
    const std::string curved = curved_roofs(c, m);
    refine_curved_buildings(c, m.buildings);
    describe_buildings(c, m);
    if (m.buildings.empty()) {
      r.status = dropped > 0 ? ParcelStatus::Failed : ParcelStatus::Empty;
      r.reason = dropped > 0 ? m.notes : "roof points form no roof plane large enough for a building";
      return r;
    }
    r.reason = m.notes;
    r.buildings = std::move(m.buildings);
    evaluate_on_parcel(s, r.buildings);
    clock.lap("evaluate");
    r.status = ParcelStatus::Ok;
    for (const auto& b : r.buildings) {
      const std::string why = building_reason(b);
      if (!why.empty()) r.reason += (r.reason.empty() ? "" : "; ") + why;
    }
    if (!curved.empty()) {
      r.status = ParcelStatus::Suspect;
      r.reason = curved + (r.reason.empty() ? "" : "; " + r.reason);
    }
  } catch (const std::exception& e) {
    r.status = ParcelStatus::Failed;
    r.reason = e.what();
    r.buildings.clear();
  }
  return r;
}

}  // namespace c3d
