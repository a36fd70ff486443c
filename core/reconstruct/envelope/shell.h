#pragma once
// Envelope sub-stage "shell": the solid's faces and the elements' faces
// welded at one set of vertices and noded, so that each shell edge is shared
// by exactly two faces and an element face equals its copy in the shell.
#include <vector>

#include "core/types.h"

namespace c3d::envelope {

// Vertices closer than tol become one (the first in `seen`, which gathers
// them), and rings lose the consecutive duplicates that leaves;
// drop_degenerate: faces left with less than 1e-6 m^2 go.
void weld_faces(std::vector<Face>& shell, double tol, std::vector<Vec3>& seen, bool drop_degenerate);

// Every vertex of the faces, holes included.
std::vector<Vec3> shell_vertices(const std::vector<Face>& shell);

// Inserts into every face edge the vertices of `verts` lying on it.
void node_faces(std::vector<Face>& shell, const std::vector<Vec3>& verts, double tol);

// Welds and nodes the solid, then the elements' faces against the same
// vertices (an outer ceiling keeps each face's height); faces the weld left
// a line, and elements left without faces, go.
void weld_shell(std::vector<Face>& solid, std::vector<Element>& elements);

// Developer aid: logs (debug) the shell edges not used by exactly two faces.
void debug_open_edges(const Building& b);

}  // namespace c3d::envelope
