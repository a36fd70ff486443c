// The curved truth buildings: their exact areas and volumes against closed
// forms by hand, against their own tessellation, and the curved town.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <nlohmann/json.hpp>

#include "core/geometry/geometry.h"
#include "core/synthetic/sample_town.h"

using namespace c3d;

namespace {

BuildingParams curved(SampleLayout l, double length, double width, double eave, double rise) {
  BuildingParams p;
  p.layout = l;
  p.length = length, p.width = width, p.eave_height = eave, p.rise = rise, p.overhang = 0;
  return p;
}

std::map<ElementType, double> exact(const Building& b) {
  std::map<ElementType, double> out;
  for (const Element& e : b.elements) out[e.type] += e.area;
  return out;
}

std::map<ElementType, double> tessellated(const Building& b) {
  std::map<ElementType, double> out;
  for (const Element& e : b.elements)
    for (const Face& f : e.faces) out[e.type] += area(f);
  return out;
}

void expect_rel(double got, double want, double tol, const char* what) {
  EXPECT_NEAR(got / want, 1.0, tol) << what << ": " << got << " against " << want;
}

}  // namespace

TEST(SampleCurved, HemisphereAndHalfCylinderMatchHandFigures) {
  // A hemisphere of radius 5 on a drum 4 m high: roof 2 pi r^2, wall 2 pi r H.
  const TruthBuilding dome = make_truth_buildings(curved(SampleLayout::Dome, 10, 10, 4, 5)).front();
  auto a = exact(dome.model);
  EXPECT_NEAR(a[ElementType::Roof], 2 * M_PI * 25, 1e-9);
  EXPECT_NEAR(a[ElementType::Wall], 2 * M_PI * 5 * 4, 1e-9);
  EXPECT_NEAR(a[ElementType::Ground], M_PI * 25, 1e-9);
  EXPECT_NEAR(dome.model.volume, M_PI * 25 * 4 + 2.0 / 3 * M_PI * 125, 1e-9);
  // A half cylinder of radius 5 and length 20 on the ground: end walls only.
  const TruthBuilding hangar = make_truth_buildings(curved(SampleLayout::GroundVault, 20, 10, 0, 5)).front();
  a = exact(hangar.model);
  EXPECT_NEAR(a[ElementType::Roof], 20 * M_PI * 5, 1e-9);
  EXPECT_NEAR(a[ElementType::Wall], M_PI * 25, 1e-9);
  EXPECT_NEAR(hangar.model.volume, 20 * M_PI * 25 / 2, 1e-9);
  int walls = 0;
  for (const Element& e : hangar.model.elements) walls += e.type == ElementType::Wall;
  EXPECT_EQ(walls, 2);
  // A cone of radius 4 and rise 3 on a drum 5 m high: slant 5, roof pi r s.
  const TruthBuilding cone = make_truth_buildings(curved(SampleLayout::Cone, 8, 8, 5, 3)).front();
  EXPECT_NEAR(exact(cone.model)[ElementType::Roof], M_PI * 4 * 5, 1e-9);
  EXPECT_NEAR(cone.model.volume, M_PI * 16 * 5 + M_PI * 16 * 3 / 3, 1e-9);
}

// Every curved layout: the exact figures and the faces the points are drawn
// on describe one surface (within the 2 mm chord: well under 0.3 %), and the
// faces close a solid of the exact volume.
TEST(SampleCurved, ExactFiguresAgreeWithTheirTessellation) {
  std::vector<BuildingParams> all = {
      curved(SampleLayout::Vault, 15, 9, 4, 3),      curved(SampleLayout::GroundVault, 18, 11, 0, 5.5),
      curved(SampleLayout::Dome, 10, 10, 5, 4),      curved(SampleLayout::ShallowDome, 12, 12, 4, 1.5),
      curved(SampleLayout::Cone, 7, 7, 6, 6),        curved(SampleLayout::OnionDome, 7, 7, 5, 8),
      curved(SampleLayout::DomeOnFlat, 14, 14, 5, 3), curved(SampleLayout::Saddle, 16, 11, 5, 3),
      curved(SampleLayout::Wave, 18, 10, 4, 2.5)};
  all[6].dome_radius = 4;
  for (const BuildingParams& p : all) {
    const TruthBuilding tb = make_truth_buildings(p).front();
    SCOPED_TRACE(tb.roof_type);
    EXPECT_TRUE(tb.exact_areas);
    const auto a = exact(tb.model), t = tessellated(tb.model);
    for (ElementType type : {ElementType::Roof, ElementType::Wall, ElementType::Ground})
      expect_rel(t.at(type), a.at(type), 1.5e-3, to_string(type));
    std::string problem;
    EXPECT_TRUE(shell_is_closed(tb.model.solid, &problem)) << problem;
    expect_rel(shell_volume(tb.model.solid), tb.model.volume, 1.5e-3, "volume");
  }
}

TEST(SampleCurved, TownHoldsEveryCurvedLayoutWithExactTruth) {
  SampleOptions opt;
  opt.curved = true;
  opt.parcels = 10;
  opt.seed = 5;
  const SampleTown town = make_sample_town(opt);
  std::set<std::string> kinds;
  for (const auto& parcel : town.truth)
    for (const TruthBuilding& tb : parcel) {
      kinds.insert(tb.roof_type);
      if (!tb.exact_areas) continue;
      // Placed in the town, the exact figures stay those of the surface.
      const TruthBuilding alone = make_truth_buildings(tb.params).front();
      EXPECT_NEAR(exact(tb.model)[ElementType::Roof], exact(alone.model)[ElementType::Roof], 1e-9) << tb.roof_type;
      EXPECT_NEAR(tb.model.volume, alone.model.volume, 1e-9) << tb.roof_type;
    }
  EXPECT_EQ(kinds, (std::set<std::string>{"vault", "ground_vault", "dome", "shallow_dome", "cone", "onion",
                                          "dome_on_flat", "gable", "saddle", "wave"}));
  const auto truth = nlohmann::json::parse(truth_json(town));
  EXPECT_EQ(truth["parcels"].size(), 10u);
  EXPECT_GT(town.cloud.points.size(), 10000u);
}
