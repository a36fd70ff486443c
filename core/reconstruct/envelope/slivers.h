#pragma once
// Envelope sub-stage "slivers": after the weld, no face may keep a vertex
// that bulges out of a nearly straight run of its boundary by less than a
// millimetre. A triangulation (ours, val3dity's) makes a sliver triangle there
// whose normal the export's 0.1 mm rounding can tilt by tens of degrees
// (error 204) although every vertex lies on the face's plane.
#include <vector>

#include "core/types.h"

namespace c3d::envelope {

// A vertex on a straight run shared by exactly two faces is dropped from
// both; one that is a corner elsewhere (a wall corner under an eave) is moved
// a little into the face, so the run turns away from it. The solid's edits are
// applied to the elements' copies of its faces, then any sliver left in an
// element face alone is straightened there.
void straighten_slivers(std::vector<Face>& solid, std::vector<Element>& elements);

}  // namespace c3d::envelope
