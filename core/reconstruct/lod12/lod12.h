#pragma once
// LoD 1.2 (the 3D-city / 3DBAG convention): one prism over a building's
// outline, from the mean terrain under it up to the 70th percentile of its own
// roof points' heights. The fallback where a building's LoD 2.2 model and its
// LoD 1.3 layers (lod13/lod13.h) cannot be made valid: a simpler, valid solid of the same kinds of elements (one flat
// roof, one wall per footprint edge, the ground), measured like any other.
#include <functional>
#include <string>
#include <vector>

#include "core/types.h"

namespace c3d {

// The prism's top: this percentile of the roof points' heights (3DBAG's LoD 1.2:
// above the eaves, below the ridge, robust to chimneys and stray points).
constexpr double kLod12RoofPercentile = 0.7;

struct PrismInput {
  std::string building_id;
  Polygon2 footprint;                 // from prism_footprint
  std::vector<bool> party_edge;       // per outer edge (outer[i] -> outer[i+1]): a party wall
  std::vector<double> roof_heights;   // z of the building's own roof points
  std::function<double(double, double)> terrain;  // local terrain z, NaN outside
  double spacing = 0.2;               // roof point spacing, m
  double default_overhang = 0.5;      // how far inside the outline the walls may stand, m
  double storey_height = 3.0;
};

// The outline as a simple valid polygon for the prism: GEOS make-valid, its
// largest part, simplified at 1 mm, rings without edges shorter than 5 mm;
// holes kept when keep_holes (and still valid), else dropped. An empty outer
// ring where nothing is left.
Polygon2 prism_footprint(const Polygon2& outline, bool keep_holes);

// The q-quantile (0..1) of `values`, linear between ranks; NaN for none.
double percentile(std::vector<double> values, double q);

// The LoD 1.2 prism, measured (areas, sigmas, volume, heights, check_solid).
// Where no prism can be built, a building without a solid whose
// solid_problem says why.
Building lod12_prism(const PrismInput& in);

// `b`, whose LoD 2.2 model is invalid (its solid_problem says why), becomes
// `prism` with lod_note saying so where the prism is valid (`prism_defect`
// ""); else `b` stays as it is and its lod_note says the prism failed too.
void adopt_prism(Building& b, Building prism, const std::string& prism_defect);

}  // namespace c3d
