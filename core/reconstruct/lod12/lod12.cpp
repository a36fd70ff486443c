#include "core/reconstruct/lod12/lod12.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "core/geometry/geometry.h"
#include "core/geometry/polygon_ops.h"
#include "core/reconstruct/envelope/footprint.h"
#include "core/reconstruct/measure/measure.h"

namespace c3d {
namespace {

// The outline is simplified at a millimetre: the validators snap at that, so
// nothing finer is geometry.
constexpr double kSimplifyM = 1e-3;
// The roof outline follows the hull of the roof points: placed to within this
// fraction of their spacing (as the LoD 2.2 roof elements' boundaries).
constexpr double kOutlineSigmaPerSpacing = 0.25;
// A prism lower than this over the terrain is no building: its roof points
// lie on the ground (bad terrain or bad points).
constexpr double kMinPrismHeightM = 0.1;

Ring2 reversed(Ring2 r) {
  std::reverse(r.begin(), r.end());
  return r;
}

// A ring without edges shorter than 5 mm (envelope::without_specks, which
// works on counter-clockwise outer rings).
Ring2 despeckled(const Ring2& ring, bool counter_clockwise) {
  if (counter_clockwise) return envelope::without_specks({ring, {}}).outer;
  return reversed(envelope::without_specks({reversed(ring), {}}).outer);
}

Ring3 at_height(const Ring2& r, double z) {
  Ring3 out;
  for (const auto& v : r) out.emplace_back(v.x(), v.y(), z);
  return out;
}

Ring3 downward(const Ring2& r, double z) {
  Ring3 out = at_height(r, z);
  std::reverse(out.begin(), out.end());
  return out;
}

// The face at height z over the footprint, facing up (the roof) or down (the ground).
Face flat_face(const Polygon2& fp, double z, bool down) {
  Face f{down ? downward(fp.outer, z) : at_height(fp.outer, z), {}};
  for (const auto& h : fp.holes) f.holes.push_back(down ? downward(h, z) : at_height(h, z));
  return f;
}

// The wall under edge a -> b of a ring (outer counter-clockwise, holes
// clockwise), facing out of the prism.
Face wall_face(const Vec2& a, const Vec2& b, double ground_z, double top_z) {
  return Face{{Vec3(a.x(), a.y(), ground_z), Vec3(b.x(), b.y(), ground_z), Vec3(b.x(), b.y(), top_z),
               Vec3(a.x(), a.y(), top_z)},
              {}};
}

// One wall element: its area known to its top (the roof points spread about
// the prism's top) and to its ends (the walls stand within an overhang of the outline).
Element wall_element(Face f, bool party, double sigma_top, double sigma_line) {
  Element e;
  e.type = party ? ElementType::PartyWall : ElementType::Wall;
  e.evidence = party ? WallEvidence::ParcelBoundary : WallEvidence::None;
  const double len = (f.ring[1] - f.ring[0]).norm(), height = f.ring[2].z() - f.ring[1].z();
  e.faces.push_back(std::move(f));
  measure_element(e);
  e.sigma_area = std::hypot(len * sigma_top, height * sigma_line);
  return e;
}

// Walls along every ring of the footprint, one per edge.
void add_walls(const PrismInput& in, double ground_z, double top_z, double sigma_top, Building& b) {
  const Polygon2& fp = in.footprint;
  std::vector<std::pair<const Ring2*, bool>> rings{{&fp.outer, true}};
  for (const auto& h : fp.holes) rings.push_back({&h, false});
  for (const auto& [ring, outer] : rings)
    for (size_t i = 0; i < ring->size(); ++i) {
      const bool party = outer && i < in.party_edge.size() && in.party_edge[i];
      Face f = wall_face((*ring)[i], (*ring)[(i + 1) % ring->size()], ground_z, top_z);
      b.solid.push_back(f);
      b.elements.push_back(wall_element(std::move(f), party, sigma_top, in.default_overhang));
    }
}

double rms_about(const std::vector<double>& values, double centre) {
  double s = 0;
  for (double v : values) s += (v - centre) * (v - centre);
  return values.empty() ? 0 : std::sqrt(s / double(values.size()));
}

Building without_prism(const std::string& id, const std::string& why) {
  Building b;
  b.id = id;
  b.solid_valid = false;
  b.solid_problem = why;
  return b;
}

}  // namespace

Polygon2 prism_footprint(const Polygon2& outline, bool keep_holes) {
  if (outline.outer.size() < 3) return {};
  Polygon2 fp = poly::largest(poly::simplify(poly::make_valid({outline}), kSimplifyM));
  if (fp.outer.size() < 3) return {};
  Polygon2 out{despeckled(fp.outer, true), {}};
  if (keep_holes)
    for (const auto& h : fp.holes) out.holes.push_back(despeckled(h, false));
  if (!out.holes.empty() && !poly::is_valid({out})) out.holes.clear();
  return poly::is_valid({out}) ? out : Polygon2{};
}

double percentile(std::vector<double> values, double q) {
  if (values.empty()) return kNaN;
  std::sort(values.begin(), values.end());
  return quantile_of_sorted(values, q);
}

Building lod12_prism(const PrismInput& in) {
  if (in.footprint.outer.size() < 3) return without_prism(in.building_id, "no valid footprint");
  if (in.roof_heights.empty()) return without_prism(in.building_id, "no roof points");
  Building b;
  b.id = in.building_id;
  b.lod = Lod::Lod12;
  try {
    b.terrain_z = envelope::mean_terrain(in.footprint, in.terrain);
  } catch (const std::runtime_error& e) {
    return without_prism(in.building_id, e.what());
  }
  const double top = percentile(in.roof_heights, kLod12RoofPercentile);
  if (!(top - b.terrain_z >= kMinPrismHeightM))
    return without_prism(in.building_id, "the roof points lie at the terrain");
  const double spread = rms_about(in.roof_heights, top);

  Element roof;
  roof.type = ElementType::Roof;
  roof.faces = {flat_face(in.footprint, top, false)};
  roof.support_points = int(in.roof_heights.size());
  roof.rmse = spread;
  measure_element(roof, kOutlineSigmaPerSpacing * in.spacing);
  b.elements.push_back(std::move(roof));
  add_walls(in, b.terrain_z, top, spread, b);
  Element ground;
  ground.type = ElementType::Ground;
  ground.faces = {flat_face(in.footprint, b.terrain_z, true)};
  measure_element(ground, in.default_overhang);
  b.elements.push_back(std::move(ground));
  b.solid.push_back(b.elements.back().faces.front());
  b.solid.push_back(b.elements.front().faces.front());
  measure_building(b, in.storey_height);
  return b;
}

void adopt_prism(Building& b, Building prism, const std::string& prism_defect) {
  if (!prism_defect.empty()) {
    b.lod_note = "no valid LoD 1.2 prism either (" + prism_defect + ")";
    return;
  }
  prism.lod_note = "LoD 2.2 invalid (" + b.solid_problem + "): LoD 1.2 prism at the " +
                   std::to_string(int(std::lround(100 * kLod12RoofPercentile))) +
                   "th percentile of its roof points";
  b = std::move(prism);
}

}  // namespace c3d
