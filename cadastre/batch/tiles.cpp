#include "cadastre/batch/tiles.h"

#include <glob.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>

#include "core/error.h"
#include "core/geometry/unique_points.h"
#include "core/io/crs.h"
#include "core/io/point_io.h"
#include "core/reconstruct/ownership/ownership.h"
#include "core/reconstruct/ownership/ownership_constants.h"

namespace c3d {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> folder_files(const std::string& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_regular_file() && is_point_file(e.path().string())) out.push_back(e.path().string());
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::string> glob_files(const std::string& pattern) {
  glob_t g{};
  std::vector<std::string> out;
  if (::glob(pattern.c_str(), 0, nullptr, &g) == 0)
    for (size_t i = 0; i < g.gl_pathc; ++i)
      if (fs::is_regular_file(g.gl_pathv[i])) out.push_back(g.gl_pathv[i]);
  ::globfree(&g);
  std::sort(out.begin(), out.end());
  return out;
}

// A tile's points a block at a time, in the working CRS, with plausible heights only.
using BlockFn = std::function<void(const std::vector<Vec3>& points, const std::vector<uint8_t>& classes)>;

struct ReadCount {
  size_t read = 0;       // points in the file
  bool classes = false;  // the file holds classes
  double first_bad = 0;  // the first height left out, for the message
  bool bad = false;
};

void for_each_block(const Tile& t, const BlockFn& fn, ReadCount* counted = nullptr) {
  if (t.held) {
    if (counted) counted->read += t.held->points.size(), counted->classes = !t.held->classes.empty();
    return fn(t.held->points, t.held->classes);
  }
  const bool reproject = !same_crs(t.crs_wkt, t.working);
  std::vector<Vec3> pts;
  std::vector<uint8_t> cls;
  for_each_point_block(t.path, [&](const PointCloud& c) {
    if (counted) counted->read += c.points.size(), counted->classes = counted->classes || !c.classes.empty();
    pts = c.points;
    if (reproject) reproject_points(pts, t.crs_wkt, t.working, t.path);
    const bool classes = c.classes.size() == c.points.size();
    cls.clear();
    size_t kept = 0;
    for (size_t i = 0; i < pts.size(); ++i) {
      if (!plausible_elevation(pts[i].z())) {
        if (counted && !counted->bad) counted->first_bad = pts[i].z(), counted->bad = true;
        continue;
      }
      pts[kept++] = pts[i];
      if (classes) cls.push_back(c.classes[i]);
    }
    pts.resize(kept);
    fn(pts, cls);
  });
}

std::string six_digits(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

}  // namespace

void Box::add(double x, double y) {
  min_x = std::min(min_x, x), max_x = std::max(max_x, x);
  min_y = std::min(min_y, y), max_y = std::max(max_y, y);
}

void Box::add(const Box& b) {
  if (b.empty()) return;
  add(b.min_x, b.min_y);
  add(b.max_x, b.max_y);
}

Box box_of(const MultiPolygon2& shape) {
  Box b;
  for (const auto& p : shape)
    for (const auto& v : p.outer) b.add(v.x(), v.y());
  return b;
}

bool is_point_file(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  for (const char* known : {".las", ".laz", ".ply", ".pcd", ".xyz", ".txt", ".csv", ".pts"})
    if (ext == known) return true;
  return false;
}

std::vector<std::string> expand_point_files(const std::vector<std::string>& args) {
  std::vector<std::string> out;
  for (const std::string& a : args) {
    std::error_code ec;
    std::vector<std::string> found;
    if (fs::is_directory(a, ec)) found = folder_files(a);
    else if (a.find_first_of("*?[") != std::string::npos && !fs::exists(a, ec)) found = glob_files(a);
    else found = {a};  // a file, or a name the reader refuses with its own message
    if (found.empty())
      throw InputError(a, fs::is_directory(a, ec) ? "folder holds no point cloud (.las .laz .ply .pcd .xyz .txt .csv)"
                                                  : "no file matches the pattern");
    out.insert(out.end(), found.begin(), found.end());
  }
  return out;
}

bool Region::holds(const Vec3& p) const {
  if (!box.holds(p)) return false;
  if (cell <= 0) return true;
  const long x = std::min(nx - 1, long((p.x() - box.min_x) / cell));
  const long y = std::min(ny - 1, long((p.y() - box.min_y) / cell));
  return keep[size_t(y * nx + x)] != 0;
}

Region region_of(const std::vector<Box>& parts) {
  Region r;
  for (const Box& b : parts) r.box.add(b);
  if (r.box.empty()) return r;
  r.cell = kRegionCellM;
  r.nx = long((r.box.max_x - r.box.min_x) / r.cell) + 1;
  r.ny = long((r.box.max_y - r.box.min_y) / r.cell) + 1;
  r.keep.assign(size_t(r.nx * r.ny), 0);
  for (const Box& b : parts) {
    if (b.empty()) continue;
    const long x0 = long((b.min_x - r.box.min_x) / r.cell), x1 = std::min(r.nx - 1, long((b.max_x - r.box.min_x) / r.cell));
    const long y0 = long((b.min_y - r.box.min_y) / r.cell), y1 = std::min(r.ny - 1, long((b.max_y - r.box.min_y) / r.cell));
    for (long y = y0; y <= y1; ++y) std::fill_n(r.keep.begin() + (y * r.nx + x0), x1 - x0 + 1, char(1));
  }
  return r;
}

RegionPoints read_region(const std::vector<Tile>& tiles, const Region& region, const ClassMapping& m) {
  PlaceFolder roof, wall;  // folded as read: the region is never held unfolded
  for (const Tile& t : tiles) {
    if (!t.extent.touches(region.box)) continue;
    for_each_block(t, [&](const std::vector<Vec3>& pts, const std::vector<uint8_t>& cls) {
      for (size_t i = 0; i < pts.size(); ++i) {
        if (!region.holds(pts[i])) continue;
        if (t.walls) wall.add(pts[i]);
        else if (cls.empty() || m.is_roof(cls[i])) roof.add(pts[i]);  // unclassified: roof
        else if (m.is_wall(cls[i])) wall.add(pts[i]);
      }
    });
  }
  return {roof.take(), wall.take()};
}

TileSurvey survey_tiles(const std::vector<Tile>& tiles, const ClassMapping& m) {
  TileSurvey s;
  std::vector<std::string> unclassified;
  for (const Tile& t : tiles) {
    ReadCount n;
    size_t kept = 0;
    for_each_block(
        t,
        [&](const std::vector<Vec3>& pts, const std::vector<uint8_t>& cls) {
          kept += pts.size();
          s.coverage.add(pts);
          for (size_t i = 0; i < pts.size(); ++i) {
            if (t.walls) ++s.wall;
            else if (cls.empty() || m.is_roof(cls[i])) ++s.roof;
            else if (m.is_wall(cls[i])) ++s.wall;
            else if (m.is_ground(cls[i])) s.ground.add(pts[i].x(), pts[i].y());
          }
        },
        &n);
    const size_t read = n.read;
    const bool classes = n.classes;
    if (read > 0 && kept == 0)
      throw InputError(t.path, "no point's height lies within " + elevation_bounds() + " (e.g. z = " +
                                   six_digits(n.first_bad) + "): check the Z scale, offset and unit");
    if (kept < read)
      s.warnings.push_back(t.path + ": " + std::to_string(read - kept) + " points with a height outside " +
                           elevation_bounds() + " left out");
    if (!t.walls && !classes) unclassified.push_back(t.path + ": no classification, all points taken as roof");
  }
  s.warnings.insert(s.warnings.end(), unclassified.begin(), unclassified.end());
  return s;
}

Dtm ground_dtm(const std::vector<Tile>& tiles, const TileSurvey& survey, const ClassMapping& m,
               const std::string& crs_wkt) {
  if (survey.ground.empty()) throw InputError("--dtm", "no DTM given and no ground-class points to build one from");
  const Box& g = survey.ground;
  GroundDtmBuilder grid(g.min_x, g.min_y, g.max_x, g.max_y, crs_wkt, 1.0, "ground-class points");
  std::vector<Vec3> ground;
  for (const Tile& t : tiles) {
    if (t.walls) continue;
    for_each_block(t, [&](const std::vector<Vec3>& pts, const std::vector<uint8_t>& cls) {
      ground.clear();
      for (size_t i = 0; i < cls.size(); ++i)
        if (!m.is_roof(cls[i]) && !m.is_wall(cls[i]) && m.is_ground(cls[i])) ground.push_back(pts[i]);
      grid.add(ground);
    });
  }
  return grid.finish();
}

std::map<CellIndex, int> DensityBlocks::around(const Box& box) {
  std::map<CellIndex, int> out;
  for (const CellIndex& b : cells_touched({box}, kDensityBlockM)) {
    auto it = known_.find(b);
    if (it == known_.end()) it = known_.emplace(b, count_block(b)).first;
    if (it->second > 0) out.emplace(b, it->second);
  }
  return out;
}

int DensityBlocks::count_block(const CellIndex& block) const {
  const long cells = std::lround(kDensityBlockM / ownership::kRoofCellM);
  const long x0 = block.first * cells, y0 = block.second * cells;
  const Box box{block.first * kDensityBlockM, block.second * kDensityBlockM, (block.first + 1) * kDensityBlockM,
                (block.second + 1) * kDensityBlockM};
  std::vector<uint16_t> count(size_t(cells * cells), 0);
  for (const Tile& t : tiles_) {
    if (t.walls || !t.extent.touches(box)) continue;
    for_each_block(t, [&](const std::vector<Vec3>& pts, const std::vector<uint8_t>& cls) {
      for (size_t i = 0; i < pts.size(); ++i) {
        if (!cls.empty() && !classes_.is_roof(cls[i])) continue;  // unclassified: roof
        const CellIndex c = roof_cell(Vec2(pts[i].x(), pts[i].y()));
        const long cx = c.first - x0, cy = c.second - y0;
        if (cx < 0 || cy < 0 || cx >= cells || cy >= cells) continue;
        uint16_t& n = count[size_t(cy * cells + cx)];
        if (n < UINT16_MAX) ++n;
      }
    });
  }
  std::map<int, size_t> histogram;  // points in a cell -> cells
  for (uint16_t n : count)
    if (n > 0) ++histogram[n];
  return typical_roof_points_per_cell(histogram);
}

std::set<CellIndex> cells_touched(const std::vector<Box>& boxes, double side) {
  std::set<CellIndex> out;
  for (const Box& b : boxes) {
    if (b.empty()) continue;
    const long x0 = long(std::floor(b.min_x / side)), x1 = long(std::floor(b.max_x / side));
    const long y0 = long(std::floor(b.min_y / side)), y1 = long(std::floor(b.max_y / side));
    for (long x = x0; x <= x1; ++x)
      for (long y = y0; y <= y1; ++y) out.emplace(x, y);
  }
  return out;
}

bool touches_any(const Box& box, const std::set<CellIndex>& cells, double side) {
  for (const CellIndex& c : cells_touched({box}, side))
    if (cells.count(c)) return true;
  return false;
}

}  // namespace c3d
