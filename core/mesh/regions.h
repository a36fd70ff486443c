#pragma once
// Region segmentation of a mesh (seed 002): faces grown into regions where
// the surface turns smoothly, each region labelled planar, curved or detail.
// The boundary-aware simplification keeps the regions' borders (simplify.h,
// `keep`), so a window frame or a ridge is not smeared into its planes.
#include <array>
#include <cstddef>
#include <vector>

#include "core/mesh/tri_mesh.h"

namespace c3d {

enum class RegionKind { Planar, Curved, Detail };
const char* region_kind_name(RegionKind k);

// Growth and labels. A face joins its neighbour's region where their normals
// differ by at most `smooth_deg`; growth goes on only from faces whose
// sharpest turn to a neighbour is at most `curvature_deg` (a face on a ridge
// joins a region but does not carry it over the ridge). A region whose
// vertices lie within `flat_m` RMS of one plane is planar; one of fewer than
// `min_faces` faces is detail; the others are curved.
struct RegionParams {
  double smooth_deg = 10, curvature_deg = 20;
  double flat_m = 0;  // the caller's: from the points' spacing
  size_t min_faces = 12;
};

struct MeshRegions {
  std::vector<int> face_region;  // per triangle; regions numbered from 0
  std::vector<RegionKind> kinds;  // per region
  size_t count(RegionKind k) const;
};

MeshRegions segment_regions(const TriMesh& mesh, const RegionParams& params);

// The edges between two regions (vertex pairs): what stage one of the
// boundary-aware simplification keeps.
std::vector<std::array<int, 2>> region_borders(const TriMesh& mesh, const MeshRegions& regions);

}  // namespace c3d
