// Stage "envelope", assembled from its sub-stages: wall evidence -> footprint
// -> roof pieces -> roof faces -> wall faces and elements -> welded shell.
#include "core/reconstruct/envelope/envelope.h"

#include <utility>
#include <vector>

#include "core/log.h"
#include "core/reconstruct/envelope/elements.h"
#include "core/reconstruct/envelope/footprint.h"
#include "core/reconstruct/envelope/roof_faces.h"
#include "core/reconstruct/envelope/roof_pieces.h"
#include "core/reconstruct/envelope/shell.h"
#include "core/reconstruct/envelope/slivers.h"
#include "core/reconstruct/envelope/wall_evidence.h"
#include "core/reconstruct/envelope/wall_faces.h"

namespace c3d {

Building build_building(const EnvelopeInput& in, FootprintApart* apart) {
  using namespace envelope;
  Building b;
  b.id = in.building_id;
  const std::vector<OutlineEdge> edges = measure_edges(in);
  const Polygon2 fp = without_specks(footprint_from_edges(edges, in.outline, in.default_overhang, apart));
  b.terrain_z = mean_terrain(fp, in.terrain);
  const RoofFaces roof = lift_roof(simple_pieces(roof_pieces(in.roof, fp), fp), in.roof);
  const RoofEdgeNoise noise = roof_edge_noise(in);
  b.elements = roof_elements(in.roof, in.fits, edges, noise, roof.by_region);

  // The shell: the walls along the footprint, the step walls between roof
  // levels, the ground floor and the roof inside the walls, in this order
  // (the weld keeps the first of close vertices).
  Facades facades = facade_walls(fp, edges, b.terrain_z, roof.inside, noise);
  std::vector<Face> solid = std::move(facades.faces);
  for (Element& e : facades.elements) b.elements.push_back(std::move(e));
  StepWalls steps = step_wall_elements(roof.inside, roof.inside_region);
  solid.insert(solid.end(), steps.faces.begin(), steps.faces.end());
  fold_sliver_steps(steps.elements, b.elements);

  const Face ground{flat(fp.outer, b.terrain_z, true), {}};
  b.elements.push_back(ground_element(ground, facades.ground));
  solid.push_back(ground);
  solid.insert(solid.end(), roof.inside.begin(), roof.inside.end());
  if (!roof.soffits.empty())
    b.elements.push_back(outer_ceiling(roof.soffits, facades.eaves));

  weld_shell(solid, b.elements);
  straighten_slivers(solid, b.elements);
  b.solid = std::move(solid);
  if (log::enabled(log::Level::Debug)) debug_open_edges(b);
  return b;
}

}  // namespace c3d
