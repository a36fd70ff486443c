#pragma once
// Envelope sub-stage "elements": faces grouped into building elements with
// their areas and the uncertainty of those areas (roofs, the ground floor,
// the outer ceiling; the walls' elements are made in wall_faces).
#include <vector>

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
// `by_region` are indexed like `roof`, `spacing` is the roof point spacing.
std::vector<Element> roof_elements(const std::vector<RoofRegion>& roof, const std::vector<PlaneFit>& fits,
                                   double spacing, const std::vector<std::vector<Face>>& by_region);

// The ground floor element of face `ground`, its area known to sigma_ground2 (m^4).
Element ground_element(const Face& ground, double sigma_ground2);

// The outer ceiling element of the soffits under the hanging roof.
Element outer_ceiling(const std::vector<Face>& soffits, const Polygon2& outline, double spacing,
                      double sigma_ground2);

}  // namespace c3d::envelope
