#include "core/reconstruct/curved_roofs.h"

#include <algorithm>
#include <cmath>

#include "core/evaluate/evaluate.h"
#include "core/geometry/geometry.h"
#include "core/geometry/polygon_ops.h"
#include "core/log.h"
#include "core/primitives/curved_building.h"
#include "core/primitives/exact_shape.h"
#include "core/primitives/height_field.h"
#include "core/primitives/revolved_roof.h"
#include "core/reconstruct/envelope/area_sigma.h"
#include "core/reconstruct/envelope/elements.h"
#include "core/reconstruct/lower_lods.h"
#include "core/reconstruct/measure/measure.h"
#include "core/reconstruct/outline/outline.h"
#include "core/reconstruct/planar_account.h"

namespace c3d {

namespace {

PrimitiveFit curved_surfaces(const Building& b, const std::vector<Vec3>& own) {
  PrimitiveSearch search;
  const RoofPlanes roof = roof_planes(b);
  search.planar_model = [&](const std::vector<Vec3>& pts) { return planar_account(roof, pts); };
  PrimitiveFit fit = find_curved_surfaces(own, search);
  log::debug(b.id + ": " + std::to_string(fit.curved.size() + fit.rejected.size()) + " curved candidates among " +
             std::to_string(own.size()) + " roof points");
  for (size_t j = 0; j < fit.rejected.size(); ++j)
    log::debug(b.id + ": not a curved roof: " + fit.rejected[j].describe() + ": " + fit.why_rejected[j]);
  return fit;
}

// The points on surface p: those of `nearby` within `tol` of it and within
// kReachM in plan of the box of its inliers among `own`. The search saw the
// building's planar segments only, which may leave out a vault's steep flanks.
std::vector<Vec3> on_surface(const Primitive& p, const std::vector<Vec3>& own, const std::vector<Vec3>& nearby,
                             double tol) {
  constexpr double kReachM = 2.0;
  Vec2 lo(1e300, 1e300), hi(-1e300, -1e300);
  for (int i : p.inliers) lo = lo.cwiseMin(own[size_t(i)].head<2>()), hi = hi.cwiseMax(own[size_t(i)].head<2>());
  lo -= Vec2(kReachM, kReachM), hi += Vec2(kReachM, kReachM);
  std::vector<Vec3> out;
  for (const Vec3& q : nearby)
    if (std::abs(p.distance(q)) <= tol && (q.head<2>().array() >= lo.array()).all() &&
        (q.head<2>().array() <= hi.array()).all())
      out.push_back(q);
  return out;
}

constexpr double kExactAgreement = 0.01;
// Vertices of a roof's outline this close to the line of their neighbours go.
constexpr double kOutlineToleranceM = 0.01;

// b replaced by `model` where there is one and, measured, it is valid; its
// reason then says the roof was modelled `how` ("on its sphere r 5.38 m").
bool adopt(Building& b, std::optional<Building> model, const std::string& how, double storey_height) {
  if (!model) return false;
  measure_building(*model, storey_height);
  if (!model->solid_valid) {
    log::info(b.id + ": its roof would be modelled " + how + ", but the model fails (" + model->solid_problem + ")");
    return false;
  }
  // The volume of the exact shape: the faces' chords leave it up to 0.3 %
  // short. A shape that disagrees with its faces by more is not kept.
  const double exact = exact_volume(model->exact);
  if (std::abs(exact - model->volume) <= kExactAgreement * model->volume) {
    model->volume = exact;
  } else if (!model->exact.parts.empty()) {
    log::info(b.id + ": its exact shape is left out: volume " + std::to_string(exact) + " m3, its faces' " +
              std::to_string(model->volume) + " m3");
    model->exact = {};
  }
  model->lod_note = "roof modelled " + how;
  b = std::move(*model);
  return true;
}

// b modelled on surface p, if valid.
bool remodel_on(Building& b, const Primitive& p, std::vector<Vec3> points, const std::vector<Vec3>& walls,
                double spacing, double storey_height) {
  CurvedBuildingInput in;
  in.building_id = b.id;
  in.roof = p;
  in.roof_points = std::move(points);
  in.wall_points = walls;
  in.ground_z = b.terrain_z;
  in.ground_sigma = envelope::kTerrainSigma;
  in.spacing = spacing;
  return adopt(b, curved_building(in), "on its " + p.describe(), storey_height);
}

// The plan segment of a vertical face: its two extreme points along `dir`.
std::pair<Vec2, Vec2> plan_extent(const Face& f, const Vec2& dir) {
  Vec2 lo = f.ring.front().head<2>(), hi = lo;
  for (const Vec3& q : f.ring) {
    if (q.head<2>().dot(dir) < lo.dot(dir)) lo = q.head<2>();
    if (q.head<2>().dot(dir) > hi.dot(dir)) hi = q.head<2>();
  }
  return {lo, hi};
}

// The planar model's wall element that stands along the edge a-b the
// longest (within kSameWallM of its line): -1 for none.
int wall_along(const Building& planar, const Vec2& a, const Vec2& b) {
  constexpr double kSameWallM = 0.2;
  const Vec2 dir = (b - a).normalized(), across(-dir.y(), dir.x());
  int best = -1;
  double longest = 0.1;
  for (size_t k = 0; k < planar.elements.size(); ++k) {
    const Element& e = planar.elements[k];
    if (e.type != ElementType::Wall && e.type != ElementType::PartyWall) continue;
    double along = 0;
    for (const Face& f : e.faces) {
      const auto [p, q] = plan_extent(f, dir);
      if (std::abs((p - a).dot(across)) > kSameWallM || std::abs((q - a).dot(across)) > kSameWallM) continue;
      along += std::max(0.0, std::min(q.dot(dir), b.dot(dir)) - std::max(p.dot(dir), a.dot(dir)));
    }
    if (along > longest) longest = along, best = int(k);
  }
  return best;
}

// The domed model's walls and ground take what the planar model knew of the
// same walls, ground and outer ceiling: party or exterior, the evidence and
// the points behind it, sigma per m2.
void inherit_walls(const Building& planar, Building& domed, double boundary_sigma) {
  for (Element& e : domed.elements) {
    // A wall along one footprint edge: its face starts with that edge on the ground.
    const bool edge_wall = e.type == ElementType::Wall && e.faces.size() == 1 && e.faces[0].ring.size() >= 4;
    int from = -1;
    if (edge_wall) from = wall_along(planar, e.faces[0].ring[0].head<2>(), e.faces[0].ring[1].head<2>());
    if (e.type == ElementType::Ground || e.type == ElementType::OuterCeiling)
      for (size_t k = 0; k < planar.elements.size(); ++k)
        if (planar.elements[k].type == e.type) from = int(k);
    if (from >= 0) {
      const Element& old = planar.elements[size_t(from)];
      e.type = old.type;
      e.evidence = old.evidence;
      e.support_points = old.support_points;
      e.rmse = old.rmse;
      e.sigma_area = old.area > 0 ? old.sigma_area * e.area / old.area : 0;
    } else if (edge_wall) {
      e.sigma_area = sigma_area_from_plane(e.faces, 0, 0, boundary_sigma);
    }
  }
}

// The planar model's roof faces in plan, united.
MultiPolygon2 roof_plan(const Building& b) {
  std::vector<MultiPolygon2> roof;
  for (const Element& e : b.elements)
    if (e.type == ElementType::Roof)
      for (const Face& f : e.faces) roof.push_back(poly::make_valid({Polygon2{to_2d(f.ring), {}}}));
  return poly::unite_all(roof);
}

// The planar model's roof outline in plan where its roof reaches past the
// footprint by more than kMinOverhangM2 (an overhang); empty otherwise.
Polygon2 overhanging_outline(const Building& b, const Polygon2& footprint) {
  constexpr double kMinOverhangM2 = 0.5;
  const Polygon2 outline = poly::largest(poly::unite(roof_plan(b), {footprint}));
  return area(outline) - area(footprint) > kMinOverhangM2 ? outline : Polygon2{};
}

// Whether wall points placed most of the planar model's walls.
bool walls_measured(const Building& b) {
  int walls = 0, measured = 0;
  for (const Element& e : b.elements)
    if (e.type == ElementType::Wall) ++walls, measured += e.evidence == WallEvidence::Measured;
  return walls > 0 && 2 * measured > walls;
}

// Where a hall's walls stand under a curved roof (a free-form one, a flat
// one carrying domes): the planar model's footprint where wall points
// placed most of its walls; else under the roof's edge, as the other curved
// buildings' walls stand without them (the planar model's assumed overhang
// is a pitched roof's eaves, which such a hall may not have).
Polygon2 hall_outline(const Building& b) {
  if (walls_measured(b)) return ground_footprint(b);
  return poly::largest(poly::simplify(roof_plan(b), kOutlineToleranceM));
}

// A flat roof's level among the points: the median height of those on no
// curved surface (within `tol`), how many lie within `tol` of it, and how
// many lie on a curved surface.
struct FlatLevel {
  double z = kNaN;
  size_t on_level = 0, on_caps = 0;
};

FlatLevel flat_level(const std::vector<Vec3>& own, const std::vector<Primitive>& caps, double tol) {
  FlatLevel f;
  std::vector<double> z;
  for (const Vec3& q : own)
    if (std::none_of(caps.begin(), caps.end(), [&](const Primitive& p) { return std::abs(p.distance(q)) <= tol; }))
      z.push_back(q.z());
  f.on_caps = own.size() - z.size();
  if (z.size() < 10) return f;
  std::nth_element(z.begin(), z.begin() + long(z.size() / 2), z.end());
  f.z = z[z.size() / 2];
  f.on_level = size_t(std::count_if(z.begin(), z.end(), [&](double v) { return std::abs(v - f.z) <= tol; }));
  return f;
}

// b modelled as a flat roof carrying its curved surfaces (domes, cones),
// where those and one level hold kWholeRoofShare of its roof points and the
// model is valid.
// The sigma of the planar model's level roof planes (within 5 deg): the
// flat roof carrying caps keeps their outline, placed and its sigma
// calibrated as any planar roof's (docs/accuracy.md).
double level_roof_sigma(const Building& planar) {
  double var = 0;
  for (const Element& e : planar.elements)
    if (e.type == ElementType::Roof && e.slope_deg < 5) var += e.sigma_area * e.sigma_area;
  return std::sqrt(var);
}

bool remodel_domed(Building& b, const PrimitiveFit& fit, const std::vector<Vec3>& own,
                   const std::vector<Vec3>& nearby, double spacing, double storey_height) {
  const double tol = 2.5 * fit.noise;
  const FlatLevel level = flat_level(own, fit.curved, tol);
  if (std::isnan(level.z) || (level.on_caps + level.on_level) * 100 < own.size() * size_t(kWholeRoofShare))
    return false;
  DomedRoofInput in;
  in.building_id = b.id;
  in.footprint = hall_outline(b);
  in.roof_outline = overhanging_outline(b, in.footprint);
  in.ground_z = b.terrain_z;
  in.roof_z = level.z;
  in.spacing = spacing;
  in.caps = fit.curved;
  for (const Primitive& p : fit.curved) in.cap_points.push_back(on_surface(p, own, nearby, tol));
  std::optional<Building> domed = domed_roof_building(in);
  if (domed) {
    Element& flat = domed->elements.front();
    flat.support_points = int(level.on_level);
    flat.rmse = fit.noise;
    flat.sigma_area = std::hypot(level_roof_sigma(b), flat.sigma_area);  // its outline's, and its caps' rims
    inherit_walls(b, *domed, spacing / 2);
  }
  std::string caps;
  for (const Primitive& p : fit.curved) caps += (caps.empty() ? "" : ", ") + p.describe();
  return adopt(b, std::move(domed), "as a flat roof carrying its " + caps, storey_height);
}

// The axis a sphere or an upright cone (within 0.35 rad, about the 20 deg
// the search allows a cone) among the candidates stands on, if one bows like
// a roof: where a surface of revolution may be.
constexpr double kUprightConeRad = 0.35;
std::optional<Vec2> upright_axis(const PrimitiveFit& fit) {
  for (const auto* list : {&fit.curved, &fit.rejected})
    for (const Primitive& p : *list)
      if (p.bow >= kMinBowM && (p.kind == PrimitiveKind::Sphere ||
                                (p.kind == PrimitiveKind::Cone && std::abs(p.axis.z()) >= std::cos(kUprightConeRad))))
        return Vec2(p.point.head<2>());
  return std::nullopt;
}

// A free profile has many parameters: it replaces a sphere or cone only
// where it fits the points materially closer (an onion's cone leaves them
// 1.5-1.9 times as far), not by the little it gains on any surface.
constexpr double kMaterialGain = 1.2;

// The RMS distance of `pts` to surface p.
double rmse_to(const Primitive& p, const std::vector<Vec3>& pts) {
  double rss = 0;
  for (const Vec3& q : pts) rss += p.distance(q) * p.distance(q);
  return pts.empty() ? 0 : std::sqrt(rss / double(pts.size()));
}

// Whether the surface of revolution is b's roof: `why` not ("" when it is);
// it must hold kWholeRoofShare of the roof points, fit them to the noise and
// beat the modelled planes by the criterion, as a curved primitive must, and
// beat `rival` (a sphere or cone holding the whole roof) where given.
// `rival_off` says whether the rival leaves the revolution's points
// materially farther: then the rival is no account of the roof either.
struct RevolutionVerdict {
  std::string why;
  bool rival_off = false;
  double rival_rmse = 0;  // the rival's RMS distance to the revolution's points
};

RevolutionVerdict judge_revolution(const Building& b, const RevolvedRoof& roof, const std::vector<Vec3>& own,
                                   double noise, const Primitive* rival) {
  std::vector<Vec3> inliers;
  for (int i : roof.inliers) inliers.push_back(own[size_t(i)]);
  const double n = double(inliers.size());
  const PlanarAccount planes = planar_account(roof_planes(b), inliers);
  const double curved = bic(roof.rmse, roof.parameters, n, noise), flat = bic(planes.rmse, 3 * planes.planes, n, noise);
  RevolutionVerdict v;
  v.rival_rmse = rival ? rmse_to(*rival, inliers) : 0;
  const double other = rival ? bic(v.rival_rmse, parameters(rival->kind), n, noise) : 0;
  v.rival_off = rival && curved + kBicMargin < other && v.rival_rmse >= kMaterialGain * roof.rmse;
  char why[200] = "";
  if (n * 100 < double(own.size()) * kWholeRoofShare)
    std::snprintf(why, sizeof why, "holds %.0f %% of the roof points", 100 * n / double(own.size()));
  else if (roof.rmse > kMaxFitOverNoise * noise)
    std::snprintf(why, sizeof why, "fits its points to %.3f m, the scan's noise is %.3f m", roof.rmse, noise);
  else if (curved + kBicMargin >= flat)
    std::snprintf(why, sizeof why, "%d planes at %.3f m do as well (BIC %.0f, %.0f)", planes.planes, planes.rmse,
                  flat, curved);
  else if (rival && !v.rival_off)
    std::snprintf(why, sizeof why, "its %s at %.3f m does as well (BIC %.0f, %.0f)", to_string(rival->kind),
                  v.rival_rmse, other, curved);
  v.why = why;
  return v;
}

// Roof points seen below where the profile starts (the drum's top) by more
// than this share: the air saw roof where the model stands its drum. Onions
// modelled well leave 0-2 % there; one whose profile was fitted above the
// bulb's widest ring left 13 % (and was `ok` with half its roof).
constexpr double kMaxShareBelowRoof = 0.05;

// The share of `pts` below the roof's start by more than 2.5 noise.
double share_below_roof(const RevolvedRoof& roof, const std::vector<Vec3>& pts, double noise) {
  size_t below = 0;
  for (const Vec3& q : pts) below += q.z() < roof.profile.front().y() - 2.5 * noise;
  return pts.empty() ? 0 : double(below) / double(pts.size());
}

// b modelled on a surface of revolution about a vertical axis (an onion
// dome, a bell-shaped roof), where a candidate points to one and it is b's
// roof by judge_revolution, better than `rival` (a sphere or cone
// holding the whole roof) where given. `unsure` says why its areas are not
// to be trusted ("" when they are): an overhanging roof over an unseen drum,
// or a rival that is no account of the roof either.
bool remodel_revolved(Building& b, const PrimitiveFit& fit, const std::vector<Vec3>& own,
                      const std::vector<Vec3>& nearby, const std::vector<Vec3>& walls, double spacing,
                      double storey_height, const Primitive* rival, std::string& unsure) {
  const std::optional<Vec2> axis = upright_axis(fit);
  if (!axis) return false;
  std::optional<RevolvedRoof> roof = fit_revolved_roof(own, *axis, fit.noise);
  if (!roof) {
    log::debug(b.id + ": no surface of revolution fits its " + std::to_string(own.size()) + " roof points");
    return false;
  }
  // Fitted again on the parcel's roof points around its axis (to half a
  // metre past its widest ring): the planar plan's own points may stop short
  // of that ring.
  std::vector<Vec3> disc;
  for (const Vec3& q : nearby)
    if ((q.head<2>() - roof->axis).norm() <= roof->profile.front().x() + 0.5) disc.push_back(q);
  const std::vector<Vec3> around = disc;  // what the built model must hold
  if (std::optional<RevolvedRoof> again = fit_revolved_roof(disc, roof->axis, fit.noise)) roof = std::move(again);
  else disc = own;
  const RevolutionVerdict verdict = judge_revolution(b, *roof, disc, fit.noise, rival);
  if (!verdict.why.empty()) {
    log::debug(b.id + ": not a roof of revolution: " + roof->describe() + ": " + verdict.why);
    // Neither surface accounts for the roof: the rival leaves the points
    // kMaterialGain farther than a profile that still misses some of them.
    if (verdict.rival_off) {
      char far[40];
      std::snprintf(far, sizeof far, "%.3f m", verdict.rival_rmse);
      unsure = "curved roof modelled with planes, areas unreliable: " + b.id + " " + rival->describe() +
               " is " + far + " off the points of its " + roof->describe() + ", which " + verdict.why;
    }
    return false;
  }
  RevolvedBuildingInput in;
  in.building_id = b.id;
  in.roof = *roof;
  in.wall_points = walls;
  in.ground_z = b.terrain_z;
  in.spacing = spacing;
  const std::string id = b.id;
  if (!adopt(b, revolved_roof_building(in), "on its " + roof->describe(), storey_height)) return false;
  if (roof->may_overhang() && !drum_seen(in))
    unsure = id + ": no wall point shows the drum under its roof, which is plumb where the points stop and may "
                  "overhang it: drum and the roof's underside unknown";
  const double below = share_below_roof(*roof, around, fit.noise);
  if (unsure.empty() && below > kMaxShareBelowRoof) {
    char why[160];
    std::snprintf(why, sizeof why, ": %.0f %% of its roof points lie below where its roof starts, on its drum",
                  100 * below);
    unsure = "curved roof, areas unreliable: " + id + why;
  }
  return true;
}

constexpr double kPointsPerPole = 16;
// A shell bends gently; a surface bending tighter than a 0.5 m radius
// somewhere over the footprint rounds off an edge between planes (a ridge,
// a step: 50-9,000 /m on Cimahi's roofs) or the noise. The curved town's
// waves, whose true bend is at most 0.7 /m, fit at up to 1.24 /m.
constexpr double kMaxBend = 2, kCurvatureStepM = 0.25;

// Whether a free-form surface is the roof whose planes are `roof`: `why` not
// ("" when it is). It must bend no tighter than kMaxBend (its largest
// curvature, `bend`), rest on kPointsPerPole points a pole (as its knots
// stand 16 points apart: a small roof's few points are no free surface) and,
// like a curved primitive, hold kWholeRoofShare of the roof points, fit them
// to the noise, bow away from flat (kMinBowM, and kMinBowOverFit times its
// fit) and beat the planes by the criterion on its points: its many poles
// pay log n each.
std::string judge_free_form(const RoofPlanes& roof, const HeightFieldRoof& hf, const std::vector<Vec3>& own,
                            double noise, const std::vector<Primitive>& curved, double bend) {
  std::vector<Vec3> inliers;
  for (int i : hf.inliers) inliers.push_back(own[size_t(i)]);
  const double n = double(inliers.size());
  const PlanarAccount planes = planar_account(roof, inliers);
  const double curved_bic = bic(hf.rmse, hf.parameters, n, noise);
  const double flat = bic(planes.rmse, 3 * planes.planes, n, noise);
  std::vector<int> all(inliers.size());
  for (size_t k = 0; k < all.size(); ++k) all[k] = int(k);
  const double bowed = bow(inliers, all);
  char why[200] = "";
  if (bend > kMaxBend)
    std::snprintf(why, sizeof why, "bends to a %.2g m radius: an edge between planes, rounded", 1 / bend);
  else if (n < kPointsPerPole * hf.parameters)
    std::snprintf(why, sizeof why, "%.0f points for %d poles: too few to tell a free surface", n, hf.parameters);
  else if (n * 100 < double(own.size()) * kWholeRoofShare)
    std::snprintf(why, sizeof why, "holds %.0f %% of the roof points", 100 * n / double(own.size()));
  else if (hf.rmse > kMaxFitOverNoise * noise)
    std::snprintf(why, sizeof why, "fits its points to %.3f m, the scan's noise is %.3f m", hf.rmse, noise);
  else if (bowed < kMinBowM || bowed < kMinBowOverFit * hf.rmse)
    std::snprintf(why, sizeof why, "nearly flat: %.3f m off its best plane, fitted to %.3f m", bowed, hf.rmse);
  else if (curved_bic + kBicMargin >= flat)
    std::snprintf(why, sizeof why, "%d planes at %.3f m do as well (BIC %.0f, %.0f)", planes.planes, planes.rmse,
                  flat, curved_bic);
  if (*why) return why;
  // A curved primitive the search kept over part of the roof (a vault whose
  // flanks it missed) is the better account of its points unless the free
  // surface fits them materially closer: then the roof stays unexplained.
  const HeightField f(hf.surface);
  for (const Primitive& p : curved) {
    double rss = 0;
    for (int i : p.inliers)
      if (size_t(i) < own.size()) rss += std::pow(f.distance(own[size_t(i)]), 2);
    const double on_its_points = std::sqrt(rss / double(std::max<size_t>(1, p.inliers.size())));
    if (on_its_points * kMaterialGain > p.rmse)
      std::snprintf(why, sizeof why, "its %s fits its points as well (%.3f m, the surface %.3f m)", to_string(p.kind),
                    p.rmse, on_its_points);
  }
  return why;
}

// A roof of fewer planes is no faceted curve: a smooth surface would smooth
// its ridges away (the criterion agrees, at a cost).
constexpr int kMinFacets = 4;

// The longest side's direction of a ring: the spline's plan frame.
Vec2 longest_side(const Ring2& ring) {
  Vec2 along = Vec2::UnitX();
  for (size_t i = 0; i < ring.size(); ++i) {
    const Vec2 side = ring[(i + 1) % ring.size()] - ring[i];
    if (side.norm() > along.norm() || i == 0) along = side;
  }
  return along;
}

// A free-form roof over its whole extent. The planar model cut the surface
// into roof levels whose outlines leave steps and notches along straight
// walls (a saddle's walls 5 % long, its ground 1.5 % short), and its points
// were taken within them. The surface is one roof: its points are the
// parcel's roof points on it (within 2.5 noise) up to its finest knot span
// (4 point spacings) beyond that outline, its edge their outline
// (outline.h), set in by the overhang the planar model's measured walls
// showed (its roof's plan against its footprint, per metre of footprint).
struct OneRoof {
  Polygon2 footprint;
  std::vector<Vec3> points;
};
constexpr double kOneRoofReachSpacings = 4, kOneRoofMarginSpacings = 2;
OneRoof one_roof(const Building& b, const Polygon2& planar, const HeightFieldRoof& hf,
                 const std::vector<Vec3>& nearby, double noise, double spacing) {
  OneRoof r;
  const MultiPolygon2 reach = poly::buffer({planar}, kOneRoofReachSpacings * spacing);
  const HeightField f(hf.surface);
  std::vector<Vec2> plan;
  for (const Vec3& q : nearby)
    if (std::abs(f.distance(q)) <= 2.5 * noise && poly::covers(reach, q.head<2>()))
      r.points.push_back(q), plan.push_back(q.head<2>());
  OutlineOptions opt;
  opt.spacing = spacing;
  // The outline's regulariser can meet two edges far out past a corner the
  // points cut off (a spike 2 m beyond any of them): the roof stands where
  // its points do, to kOneRoofMarginSpacings past their convex hull.
  const MultiPolygon2 held = poly::buffer(poly::convex_hull(plan), kOneRoofMarginSpacings * spacing);
  const Polygon2 edge = poly::largest(poly::intersect({roof_outline(plan, opt)}, held));
  if (edge.outer.size() < 3) return {};
  r.footprint = edge;
  if (!walls_measured(b)) return r;
  const double overhang = (area(roof_plan(b)) - area(planar)) / envelope::perimeter(planar.outer);
  if (overhang <= kOutlineToleranceM) return r;
  r.footprint = poly::largest(poly::buffer({edge}, -overhang));
  if (r.footprint.outer.size() < 3) return {};
  return r;
}

// Each footprint edge's sigma as the outline stage placed it from the roof
// points' density (envelope::RoofEdgeNoise, docs/accuracy.md).
void edge_sigma(const Polygon2& foot, double noise, double density, FreeFormInput& in) {
  const envelope::RoofEdgeNoise n{noise, density};
  std::vector<const Ring2*> rings{&foot.outer};
  for (const Ring2& h : foot.holes) rings.push_back(&h);
  double sampled = 0;
  for (const Ring2* ring : rings)
    for (size_t i = 0; i < ring->size(); ++i) {
      const double length = ((*ring)[(i + 1) % ring->size()] - (*ring)[i]).norm();
      in.edge_sigma.push_back(n.edge(length));
      sampled += std::max(0.0, sampled_edge_length(length));
    }
  in.common_sigma = n.common(sampled);
}

// b modelled under a free-form roof (height_field.h), where its planes leave
// the roof points farther than the noise allows or take many facets, and a
// B-spline height field over its footprint is its roof by judge_free_form;
// then fitted again over the roof's whole extent (one_roof).
bool remodel_free_form(Building& b, const std::vector<Vec3>& own, const std::vector<Vec3>& nearby,
                       const PrimitiveFit& fit, double spacing, double storey_height) {
  const double noise = fit.noise;
  const RoofPlanes roof = roof_planes(b);
  const PlanarAccount planes = planar_account(roof, own);
  if (planes.rmse <= kMaxFitOverNoise * noise && planes.planes < kMinFacets) return false;
  FreeFormInput in;
  in.footprint = hall_outline(b);
  if (in.footprint.outer.size() < 3) return false;
  const Ring2& ring = in.footprint.outer;
  std::optional<HeightFieldRoof> hf = fit_height_field(own, noise, spacing, ring, longest_side(ring));
  if (!hf) return false;
  Vec2 lo = ring.front(), hi = lo;
  for (const Vec2& q : ring) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
  const double bend = HeightField(hf->surface).max_curvature(lo, hi, kCurvatureStepM);
  const std::string why = judge_free_form(roof, *hf, own, noise, fit.curved, bend);
  if (!why.empty()) {
    log::debug(b.id + ": not a free-form roof: " + hf->describe() + ": " + why);
    return false;
  }
  const OneRoof whole = one_roof(b, in.footprint, *hf, nearby, noise, spacing);
  std::optional<HeightFieldRoof> refit;
  if (!whole.points.empty())
    refit = fit_height_field(whole.points, noise, spacing, whole.footprint.outer, longest_side(whole.footprint.outer));
  if (refit) hf = refit, in.footprint = whole.footprint;
  in.building_id = b.id;
  in.roof = hf->surface;
  in.ground_z = b.terrain_z;
  edge_sigma(oriented(in.footprint), noise, double(hf->inliers.size()) / area(in.footprint), in);
  std::optional<Building> model = free_form_building(in);
  if (model) {
    log::debug(b.id + ": free-form roof of " + std::to_string(model->elements.front().faces.size()) + " triangles");
    Element& roof = model->elements.front();
    roof.support_points = int(hf->inliers.size());
    roof.rmse = hf->rmse;
    inherit_walls(b, *model, spacing / 2);
  }
  return adopt(b, std::move(model), "under its " + hf->describe(), storey_height);
}

}  // namespace

std::string model_curved_roof(Building& b, const std::vector<Vec3>& own, const std::vector<Vec3>& nearby,
                              const std::vector<Vec3>& walls, double spacing, double storey_height) {
  const PrimitiveFit fit = curved_surfaces(b, own);
  std::string unsure;
  const Primitive* whole =
      fit.curved.size() == 1 && fit.curved.front().share >= kWholeRoofShare ? &fit.curved.front() : nullptr;
  const bool round = whole && whole->kind != PrimitiveKind::Cylinder;
  if (round && remodel_revolved(b, fit, own, nearby, walls, spacing, storey_height, whole, unsure)) return unsure;
  if (!unsure.empty()) return unsure;
  if (whole && remodel_on(b, *whole, on_surface(*whole, own, nearby, 2.5 * fit.noise), walls, spacing, storey_height))
    return "";
  if (!fit.curved.empty() && remodel_domed(b, fit, own, nearby, spacing, storey_height)) return "";
  if (!round && remodel_revolved(b, fit, own, nearby, walls, spacing, storey_height, nullptr, unsure)) return unsure;
  if (remodel_free_form(b, own, nearby, fit, spacing, storey_height)) return "";
  if (fit.curved.empty()) return "";
  std::string note;
  for (const Primitive& q : fit.curved)
    note += (note.empty() ? "" : ", ") + b.id + " " + q.describe() + " (" + std::to_string(q.share) +
            " % of its roof points)";
  return "curved roof modelled with planes, areas unreliable: " + note;
}

}  // namespace c3d
