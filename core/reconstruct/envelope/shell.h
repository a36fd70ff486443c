#pragma once
// Envelope sub-stage "shell": the solid's faces and the elements' faces
// welded at one set of vertices and noded, so that each shell edge is shared
// by exactly two faces and an element face equals its copy in the shell.
#include <vector>

#include "core/geometry/welding.h"
#include "core/types.h"

namespace c3d::envelope {

// Vertices closer than the welder's tolerance become one (the first it kept),
// and rings lose the consecutive duplicates that leaves; drop_degenerate:
// faces left with less than 1e-6 m^2 go.
void weld_faces(std::vector<Face>& shell, Welder<Vec3>& welder, bool drop_degenerate);

// Every vertex of the faces, holes included.
std::vector<Vec3> shell_vertices(const std::vector<Face>& shell);

// Inserts into every face edge the noder's vertices lying on it.
void node_faces(std::vector<Face>& shell, const EdgeNoder<Vec3>& noder);

// Welds and nodes the solid, then the elements' faces against the same
// vertices (an outer ceiling keeps each face's height); faces the weld left
// a line, and elements left without faces, go.
void weld_shell(std::vector<Face>& solid, std::vector<Element>& elements);

// Developer aid: logs (debug) the shell edges not used by exactly two faces.
void debug_open_edges(const Building& b);

}  // namespace c3d::envelope
