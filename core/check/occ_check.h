#pragma once
// Independent cross-check of a shell's area and volume with OpenCASCADE
// (B-rep faces sewn into a solid, BRepGProp). OCC headers stay in occ_check.cpp.
#include <string>
#include <vector>

#include "core/types.h"

namespace c3d {

struct OccMeasures {
  bool ok = false;       // faces built, sewn into one closed shell, solid made
  double area = 0;       // BRepGProp::SurfaceProperties of the sewn faces, m2
  double volume = 0;     // BRepGProp::VolumeProperties of the solid, m3 (> 0 when
                         // the faces were outward oriented)
  int free_edges = 0;    // edges of one face only after sewing (0 when closed)
  std::string problem;   // why not ok
};

// Builds one planar face per Face (outer wire + hole wires on the face plane),
// sews them (tolerance 1e-5 m), makes a solid of the shell.
OccMeasures occ_measure(const std::vector<Face>& shell);

}  // namespace c3d
