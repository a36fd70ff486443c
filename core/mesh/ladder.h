#pragma once
// A building's mesh at four levels of detail (issue 50; seeds 002, 003),
// named as the seed names them: level 4 dense, levels 3 and 2 simplified,
// level 1 a closed hull of a few hundred faces at most.
#include <array>
#include <functional>
#include <string>
#include <vector>

#include "core/mesh/dense.h"
#include "core/mesh/mesh_metrics.h"
#include "core/mesh/regions.h"
#include "core/mesh/simplify.h"

namespace c3d {

// Face budgets of the simplified levels, as shares of level 4's faces, and
// level 1's ceiling: what the issue asks (level 3 at 10 % at most, level 1
// a few hundred faces), level 2 between. A small building's level 2 may have
// fewer faces than its level 1.
constexpr double kLevel3Share = 0.10, kLevel2Share = 0.02;
constexpr size_t kLevel1MaxFaces = 400;

struct MeshLevel {
  int level = 0;  // 1 (hull) .. 4 (dense)
  TriMesh mesh;
  MeshMetrics metrics;
  double seconds = 0;  // CPU time to make this level from the one it comes from
  std::vector<int> face_region;      // levels 2 to 4: each face's region of level 4 (regions.h)
  std::vector<RegionShape> planar;   // levels 2 to 4: level 4's planar regions here (seed 002's table)
  PlanarChange change;               // levels 2 and 3: those regions against level 4's
  Spread border_shift;               // levels 2 and 3: level 4's region borders' distance to this level (m)
};

struct MeshLadder {
  PointSpacing spacing;
  DenseMethod method = DenseMethod::AdvancingFront;
  Simplifier simplifier = Simplifier::BoundaryAware;
  size_t trimmed = 0;              // level 4's faces dropped as farther than two spacings from the points
  double hull_alpha = 0, hull_offset = 0;  // level 1's wrap (simplify.h, Wrap), m
  MeshRegions regions;  // of level 4 (regions.h)
  std::array<MeshLevel, 4> levels;  // levels[0] is level 1
  const MeshLevel& level(int k) const { return levels[size_t(k - 1)]; }
};

// Points that close level 1's hull where no scan sees (the footprint at the
// terrain, sampled at the points' mean spacing, given): without them a wrap
// of a roof and walls is a thin shell.
using HullClosure = std::function<std::vector<Vec3>(double spacing)>;

// The four levels from one building's points (roof, walls, and a wall
// cloud where given), in the caller's local frame, level 1 closed by
// `closure` where given. Fewer than 4 points: an empty ladder (every level
// without faces).
// Levels 3 and 2 (re)made from the ladder's level 4 and its regions by
// `simplifier`, and measured against the points, with level 4's planar
// region shapes they are compared with: another simplification of
// the same dense level (CGAL's advancing front depends on where the heap put
// its triangulation, so a second ladder of the same points may differ).
void simplify_levels(MeshLadder& ladder, Simplifier simplifier, const std::vector<Vec3>& points);

// Levels 3 and 2 are made by `simplifier` (the boundary-aware one; the
// others for comparison, docs/meshes.md).
MeshLadder mesh_ladder(const std::vector<Vec3>& points, DenseMethod method = DenseMethod::AdvancingFront,
                       const HullClosure& closure = {}, Simplifier simplifier = Simplifier::BoundaryAware);

}  // namespace c3d
