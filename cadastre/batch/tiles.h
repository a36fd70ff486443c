#pragma once
// Many files as one cloud. --cloud and --walls name files, folders or globs;
// each file is a tile known by its extent (a LAS/LAZ header's bounds, or one
// pass over the points of a format without them), and the points of a region
// are read from the tiles that touch it, a block at a time, keeping only those
// inside: no tile is ever held whole (docs/inputs.md, "Tiles").
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "cadastre/batch/plausibility.h"
#include "core/io/dtm_io.h"
#include "core/reconstruct/scene/roof_density.h"
#include "core/types.h"

namespace c3d {

// A box in plan, world coordinates of the working CRS.
struct Box {
  double min_x = 1e300, min_y = 1e300, max_x = -1e300, max_y = -1e300;
  bool empty() const { return min_x > max_x; }
  void add(double x, double y);
  void add(const Box& b);
  Box grown(double m) const { return {min_x - m, min_y - m, max_x + m, max_y + m}; }
  bool touches(const Box& b) const {
    return !empty() && !b.empty() && min_x <= b.max_x && b.min_x <= max_x && min_y <= b.max_y && b.min_y <= max_y;
  }
  bool holds(const Vec3& p) const { return p.x() >= min_x && p.x() <= max_x && p.y() >= min_y && p.y() <= max_y; }
};

Box box_of(const MultiPolygon2& shape);

// A name with a point cloud's extension (.las .laz .ply .pcd .xyz .txt .csv .pts).
bool is_point_file(const std::string& path);

// The point-cloud files the arguments name, in order: a file as it is, a
// folder's point clouds (.las .laz .ply .pcd .xyz .txt .csv .pts) sorted by
// name, a glob's matches sorted. Throws InputError naming an argument that
// names nothing.
std::vector<std::string> expand_point_files(const std::vector<std::string>& args);

struct Tile {
  std::string path;
  bool walls = false;    // a --walls file: every point is a wall point
  std::string crs_wkt;   // its points' CRS: its own, or the one assumed for it
  std::string working;   // the batch's CRS, where the points are reprojected to when it differs
  Box extent;            // in the working CRS
  // --classify: the cloud classified in memory (working CRS), read from here, not from the file.
  std::shared_ptr<const PointCloud> held;
  uint64_t points = 0;  // in the file (its header's count): with the extent, the tile's density
};

// A region is read this much wider than its points are needed: copies within
// kSamePlaceM fold into one place alike in a region and in the whole cloud
// wherever they lie this far inside the region's edge.
constexpr double kRegionMarginM = 1.0;

// The points of a region: roof and wall points inside it (boundary
// included), working CRS, each class one point per place (one_per_place), in
// the order of the tiles and of the points in their files, as a whole read
// would give them.
struct RegionPoints {
  std::vector<Vec3> roof, wall;
};

// Where a region keeps points: its box, and within it the cells of a
// kRegionCellM grid that touch any of its parts. A chunk's parts are its
// parcels' boxes grown by the reach: its points without the gaps its box
// spans between them (a run of the Hilbert order can be L-shaped).
struct Region {
  Box box;
  double cell = 0;  // m; 0: the whole box
  long nx = 0, ny = 0;
  std::vector<char> keep;  // nx * ny, row by row from the box's min corner
  bool holds(const Vec3& p) const;
};
constexpr double kRegionCellM = 5.0;  // fine enough to follow parcels, few cells for a chunk
Region region_of(const std::vector<Box>& parts);

RegionPoints read_region(const std::vector<Tile>& tiles, const Region& region, const ClassMapping& classes);
inline RegionPoints read_region(const std::vector<Tile>& tiles, const Box& box, const ClassMapping& classes) {
  return read_region(tiles, Region{box}, classes);
}

// What one pass over every tile tells before any region is read.
struct TileSurvey {
  PointCoverage coverage;  // where the clouds have points of any class
  Box ground;              // the ground-class points' extent
  size_t roof = 0, wall = 0;
  std::vector<std::string> warnings;  // once per file: heights left out, no classification
};
TileSurvey survey_tiles(const std::vector<Tile>& tiles, const ClassMapping& classes);

// The DTM dtm_from_points builds from every ground-class point, a pass over
// the tiles (the grid is held whole: 4 bytes per cell).
Dtm ground_dtm(const std::vector<Tile>& tiles, const TileSurvey& survey, const ClassMapping& classes,
               const std::string& crs_wkt);

// The scan's roof density by block (core/reconstruct/scene/roof_density.h). A
// block is counted once, when a chunk first needs it: one pass over the
// tiles that touch it, each roof point counted in its cell (a count per cell
// for the block, 8 MB whatever the scan's density). Copies of a point count
// as points here, unlike a region's one per place: a count, not a model.
class DensityBlocks {
 public:
  DensityBlocks(const std::vector<Tile>& tiles, const ClassMapping& classes) : tiles_(tiles), classes_(classes) {}
  // The typical counts of the blocks the box (world coordinates) touches.
  std::map<CellIndex, int> around(const Box& box);

 private:
  int count_block(const CellIndex& block) const;
  const std::vector<Tile>& tiles_;
  ClassMapping classes_;
  std::map<CellIndex, int> known_;
};

// The cells of a grid of `side` metres (world coordinates, from 0) that the
// boxes touch, and whether a box touches one of them: which tiles and blocks
// a run's parcels can need, without a pass over every tile per parcel.
std::set<CellIndex> cells_touched(const std::vector<Box>& boxes, double side);
bool touches_any(const Box& box, const std::set<CellIndex>& cells, double side);

}  // namespace c3d
