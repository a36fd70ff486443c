#pragma once
// Region segmentation of a mesh (seed 002): faces grown into regions where
// the surface turns smoothly, each region labelled planar, curved or detail.
// The boundary-aware simplification keeps the regions' borders (simplify.h)
// in its first stage, so a window frame or a ridge is not smeared into its
// planes; the planar regions' shapes tell what it kept.
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
// A face also joins a region whose plane (its faces' mean normal through
// their mean centre) its corners lie within `flat_m` of, turned by at most
// `on_plane_deg` from it: on a noisy plane a small face tilts steeply.
struct RegionParams {
  double smooth_deg = 10, curvature_deg = 20, on_plane_deg = 45;
  double flat_m = 0;  // the caller's: from the points' spacing and noise
  size_t min_faces = 12;
};

struct MeshRegions {
  std::vector<int> face_region;  // per triangle; regions numbered from 0
  std::vector<RegionKind> kinds;  // per region
  // Each planar region's extremes on the mesh segmented (planar_extremes,
  // below): the lighter levels keep them, so their extents are measured
  // against the same vertices.
  std::vector<Vec3> extremes;
  size_t count(RegionKind k) const;
};

MeshRegions segment_regions(const TriMesh& mesh, const RegionParams& params);

// A planar region's frame: its vertices' centre and principal axes (PC1 and
// PC2 along its plane, PC3 across it), taken on the dense level so the
// lighter levels are measured along the same axes.
struct RegionFrame {
  int region = -1;
  Vec3 centre = Vec3::Zero();
  std::array<Vec3, 3> axes{};
};
std::vector<RegionFrame> planar_frames(const TriMesh& mesh, const MeshRegions& regions);

// Seed 002's table of segments: a region's vertices' ranges along its frame's
// axes (m), its extent (length along PC1, width along PC2) and thickness
// (along PC3). A region with no face in the mesh has no shape (`faces` 0).
struct RegionShape {
  int region = -1;
  size_t faces = 0;
  double length = 0, width = 0, thickness = 0;
};
std::vector<RegionShape> region_shapes(const TriMesh& mesh, const std::vector<int>& face_region,
                                       const std::vector<RegionFrame>& frames);

// Each planar region's extremes: its vertices farthest either way along its
// frame's first two axes, whose distances are its length and width.
std::vector<Vec3> planar_extremes(const TriMesh& mesh, const MeshRegions& regions);

// The vertices where faces of two or more regions meet: ridges, frames,
// sills (the open border is not one).
std::vector<Vec3> border_vertices(const TriMesh& mesh, const std::vector<int>& face_region);

// A lighter level's planar regions against the dense level's: how many there
// are, how many it lost (no face left), the largest change of a kept region's
// length or width, and the largest thickness (m).
struct PlanarChange {
  size_t regions = 0, lost = 0;
  double extent_change = 0, thickness = 0;
};
PlanarChange planar_change(const std::vector<RegionShape>& dense, const std::vector<RegionShape>& light);

}  // namespace c3d
