#pragma once
// Envelope sub-stage "area sigma": the error model behind every element's
// area sigma (docs/accuracy.md, "Area σ calibration"). Each area error is a
// sum of a few position errors: a roof-outline edge's (placed by maximum
// likelihood from the roof points' density), a wall's (fitted to its points,
// or set back from its roof edge by an overhang) and the roof planes'. Errors
// of different edges are independent, but for the parts one building's edges
// share (the noise fitted to all of a roof's edges at once; the one overhang
// assumed for all its unseen walls): Element::sigma_shared carries those, and
// totals add them linearly.
#include <vector>

#include "core/geometry/geometry.h"
#include "core/reconstruct/envelope/wall_evidence.h"
#include "core/types.h"

namespace c3d::envelope {

// The roof points as the outline stage saw them: their planimetric noise
// (the planes' fit rms: the noise is taken isotropic) and plan density.
struct RoofEdgeNoise {
  double noise = 0;    // m
  double density = 0;  // points per m^2 of roof plan
  // 1-sigma position of a roof-outline edge of length `length`, its own part:
  // the Cramér–Rao bound of the blurred-edge model, noise / (0.90 rho l),
  // l the part of it whose points place it (sampled_edge_length).
  double edge(double length) const;
  // The part all edges of a roof share, `sampled` m of them read: the noise
  // is fitted to all of them at once, and an edge moves 0.66 m per m of it.
  double common(double sampled) const;
  double plane_z = 0;  // 1-sigma height of a roof plane at its edge (offset: noise / sqrt(n)), m
};
RoofEdgeNoise roof_edge_noise(const EnvelopeInput& in);

// The free (not party) outline's length whose points place it.
double sampled_perimeter(const std::vector<OutlineEdge>& edges);

// The walls' foot level (one for all of a building's walls) is the terrain
// model's mean over the footprint, read every half metre: another reading of
// the same model (the sample towns' truth averages its 1 m cells) differs by
// 4.9 mm rms on their rolling ground. A survey's own DTM error is not in it.
constexpr double kTerrainSigma = 0.005;  // m

// How the position of the wall under one footprint edge errs (outward
// positive), split as the areas need it.


struct WallPositionError {
  double wall = 0;          // the wall's own, independent of other edges (m)
  double wall_shared = 0;   // shared by the building's edges (one assumed overhang, one fitted noise)
  double eave = 0;          // the hanging roof's depth beyond it, own part (m)
  double eave_shared = 0;   // and shared part
};
WallPositionError wall_position_error(const OutlineEdge& e, const RoofEdgeNoise& noise, double sampled);

// How much the walls' area grows per metre the wall along footprint edge i
// (fp.outer[i] -> [i+1], face `wall` from ground_z) moves outward: the
// crossing walls at its ends lengthen (at a convex corner; shorten at a
// concave one) by its height there, and its top follows the roof underside
// across it (lower under an eave). The parts are booked with the element
// whose area they change, the crossing ones with this wall where it is of the
// same type (one error, so one element: they add in quadrature to the total).
struct WallSensitivity {
  double at_a = 0, at_b = 0, top = 0;  // m^2 per m
};
WallSensitivity wall_area_sensitivity(const Ring2& fp, size_t i, const Face& wall, double ground_z,
                                      const std::vector<Face>& inside);

}  // namespace c3d::envelope
