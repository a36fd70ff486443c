#pragma once
// Envelope sub-stage "elements": faces grouped into building elements with
// their areas and the uncertainty of those areas (roofs, the ground floor,
// the outer ceiling; the walls' elements are made in wall_faces).
#include <vector>

#include "core/reconstruct/envelope/area_sigma.h"
#include "core/reconstruct/planes/planes.h"
#include "core/reconstruct/roof/roof.h"
#include "core/types.h"

namespace c3d::envelope {

// An element of `type` holding `faces`, its area and plan area summed (an
// outer ceiling's area is its plan area).
Element make_element(ElementType type, std::vector<Face> faces);

double perimeter(const Ring2& r);

// Compass direction (degrees from north, clockwise) a face's normal points to.
double azimuth_of(const Face& f);

const Face& widest_face(const Element& e);

// One roof element per region with faces, overhang included; `fits` and
// `by_region` are indexed like `roof`; `edges` the outline's, whose positions
// err as `noise` says (area_sigma.h).
std::vector<Element> roof_elements(const std::vector<RoofRegion>& roof, const std::vector<PlaneFit>& fits,
                                   const std::vector<OutlineEdge>& edges, const RoofEdgeNoise& noise,
                                   const std::vector<std::vector<Face>>& by_region);

// The ground floor element of face `ground`, its area known to `sigma` (the
// walls' positions, Facades::ground).
Element ground_element(const Face& ground, const SharedSigma& sigma);

// The outer ceiling element of the soffits under the hanging roof, its area
// known to `sigma` (the hanging roof's depth, Facades::eaves).
Element outer_ceiling(const std::vector<Face>& soffits, const SharedSigma& sigma);

}  // namespace c3d::envelope
