#pragma once
// LoD 1.3 (the 3D-city convention; the layering and progressive
// regularisation of the satellite inverse-procedural seed paper): a tree of
// height layers from the building's own roof points (layers.h), each layer's
// outline made regular while it keeps its IoU with the layer's points
// (regularise.h), stacked into one closed solid (layer_solid.h) of flat roof
// parts, step walls, outer and party walls and the ground, measured like any
// other building. The fallback where LoD 2.2 cannot be made valid, before the
// LoD 1.2 prism; usable for any building.
#include <functional>
#include <string>
#include <vector>

#include "core/reconstruct/lod12/lod12.h"
#include "core/types.h"

namespace c3d {

// What the layering found, for the note and the tests.
struct Lod13Summary {
  int layers = 0;                       // in the solid
  std::vector<double> heights;          // each layer's top above the terrain, m
  std::vector<double> iou_found, iou;   // per layer but the footprint: its outline's IoU as found, as kept
  double cell = 0;                      // the surface model's cell, m
};

// The LoD 1.3 of a building over in.footprint (with its party edges, terrain,
// spacing, overhang and storey height) from its own roof points. A building
// with lod "1.3" and a lod_note naming its layers where its solid passes
// check_solid and `face_defect` (when given: why its faces would fail, ""
// when they pass); a solid that fails is tried again without its smallest
// layers. Where none passes, solid_valid is false and solid_problem says why.
Building lod13_layers(const PrismInput& in, const std::vector<Vec3>& roof_points,
                      const std::function<std::string(const Building&)>& face_defect = {},
                      Lod13Summary* summary = nullptr);

// `b`, whose LoD 2.2 model is invalid (its solid_problem says why), becomes
// `layered` (valid: its lod_note names its layers), with a note that says why.
void adopt_lod13(Building& b, Building layered);

}  // namespace c3d
