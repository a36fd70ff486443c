// 3D Tiles 1.1 of a batch (`--formats 3dtiles`, docs/exports.md "3D Tiles"):
// OUT/3dtiles/tileset.json and one glTF content tile per cell of kCellM
// metres, under a quadtree of the cells whose parents hold the largest
// buildings' LoD 1.2 prisms. Pages are spooled per cell as they come, so the
// writer holds one tile's buildings at a time and the cells' bounds.
#include <algorithm>
#include <climits>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <stdexcept>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "core/io/crs.h"
#include "ifc_citygml/export.h"
#include "ifc_citygml/spool.h"
#include "ifc_citygml/tile_building.h"
#include "ifc_citygml/tile_content.h"
#include "ifc_citygml/tileset_viewer.h"
#include "valuation/valuation_types.h"

namespace c3d {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using tiles::TileBuilding;

constexpr double kCellM = 250;  // a content tile's side: a few hundred buildings in a town

using CellKey = std::pair<long, long>;

using Bounds = Eigen::AlignedBox3d;  // world coordinates; empty until extended

// A tile's place on the Earth: the transform of its content (metres of the
// CRS east, north and up from `centre`) to Earth-centred, Earth-fixed
// metres, and the region (radians, heights) holding `b`. The columns are the
// CRS's own unit steps carried to EPSG:4978 at the centre, so grid
// convergence and scale are in them; heights are taken as ellipsoidal.
struct Georef {
  std::vector<double> transform;  // 16, column-major
  std::vector<double> region;     // west, south, east, north, min height, max height
};

Georef georef(const std::string& crs, const Vec3& centre, const Bounds& b) {
  std::vector<Vec3> axes{centre, centre + Vec3::UnitX(), centre + Vec3::UnitY(), centre + Vec3::UnitZ()};
  reproject_points(axes, crs, wkt_from_epsg(4978), "3dtiles");
  Georef g;
  for (int c = 0; c < 3; ++c) {
    const Vec3 col = axes[size_t(c) + 1] - axes[0];
    g.transform.insert(g.transform.end(), {col.x(), col.y(), col.z(), 0.0});
  }
  g.transform.insert(g.transform.end(), {axes[0].x(), axes[0].y(), axes[0].z(), 1.0});
  std::vector<Vec3> rim;  // the plan's edges, sampled: a projected edge bows in longitude and latitude
  constexpr int kSteps = 8;
  for (int k = 0; k <= kSteps; ++k) {
    const double t = double(k) / kSteps;
    const Vec3 at = b.min() + t * (b.max() - b.min());
    rim.insert(rim.end(), {Vec3(at.x(), b.min().y(), 0), Vec3(at.x(), b.max().y(), 0), Vec3(b.min().x(), at.y(), 0),
                           Vec3(b.max().x(), at.y(), 0)});
  }
  reproject_points(rim, crs, wkt_from_epsg(4979), "3dtiles");
  Bounds ll;
  for (const Vec3& p : rim) ll.extend(p * (M_PI / 180));
  constexpr double kMarginRad = 1e-8;  // 6 cm: the samples between the corners
  g.region = {ll.min().x() - kMarginRad, ll.min().y() - kMarginRad, ll.max().x() + kMarginRad,
              ll.max().y() + kMarginRad, b.min().z(), b.max().z()};
  return g;
}

// A tile of the quadtree being built: its JSON, the world box of its
// buildings, and the cells under it.
struct Node {
  json tile;
  Bounds bounds;
  std::vector<CellKey> cells;
};

// A parent tile holds the LoD 1.2 prisms of at most about this many
// buildings of its cells, the largest by ground area.
constexpr size_t kCoarseBuildings = 2000;

class TilesetWriter : public ExportWriter {
 public:
  TilesetWriter(const BatchModel& header, const std::string& dir) : crs_(header.crs_wkt), dir_(dir) {
    if (crs_.empty())
      throw std::runtime_error(dir + ": 3D Tiles need the batch's CRS to place the buildings on the Earth; it has none");
    fs::create_directories(fs::path(dir) / "tiles");
    fs::create_directories(spool_dir());
  }
  bool carries_values() const override { return true; }
  void values(const std::vector<ParcelValuation>& v) override { values_ = v; }
  void add(const BatchModel& page) override {
    std::map<std::string, const ParcelValuation*> by_parcel;
    for (const auto& x : values_) by_parcel[x.parcel_id] = &x;
    for (const ParcelResult& r : page.results) {
      const auto it = by_parcel.find(r.parcel_id);
      const ParcelValuation* v = it == by_parcel.end() ? nullptr : it->second;
      for (const Building& b : r.buildings) {
        const TileBuilding full = tiles::tile_building(b, r, v, page.frame);
        spool(full, tiles::coarse_building(b, full, page.frame));
      }
    }
    values_.clear();
  }
  std::vector<std::string> finish() override;

 private:
  std::string crs_, dir_;
  std::vector<ParcelValuation> values_;
  std::map<CellKey, Bounds> cells_;

  std::string spool_dir() const { return (fs::path(dir_) / ".spool").string(); }
  static std::string name(const CellKey& k) { return std::to_string(k.first) + "_" + std::to_string(k.second); }
  std::string spool_of(const CellKey& k, const char* kind) const {
    return (fs::path(spool_dir()) / (name(k) + kind + ".msgpack")).string();
  }

  void spool(const TileBuilding& full, const TileBuilding& coarse) {
    Bounds box;
    for (const auto& e : full.elements)
      for (const auto& f : e.faces)
        for (const Vec3& p : f) box.extend(p);
    if (box.isEmpty()) return;  // no faces
    const Vec3 mid = box.center();
    const CellKey k{long(std::floor(mid.x() / kCellM)), long(std::floor(mid.y() / kCellM))};
    cells_[k].extend(box);
    exp::append_record(spool_of(k, ""), tiles::to_bytes(full));
    exp::append_record(spool_of(k, ".coarse"), tiles::to_bytes(coarse));
  }
  json content(const std::vector<TileBuilding>& buildings, const Bounds& b, const std::string& uri);
  json leaf(const CellKey& k, const Bounds& b);
  void coarse(Node& parent, const std::string& uri);
};

// The tile of `buildings` written as `uri`: its content, transform and region.
json TilesetWriter::content(const std::vector<TileBuilding>& buildings, const Bounds& b, const std::string& uri) {
  const Vec3 centre(b.center().x(), b.center().y(), b.min().z());
  const std::vector<unsigned char> glb = tiles::tile_glb(buildings, centre);
  std::ofstream out(fs::path(dir_) / uri, std::ios::binary);
  out.write(reinterpret_cast<const char*>(glb.data()), std::streamsize(glb.size()));
  if (!out) throw std::runtime_error((fs::path(dir_) / uri).string() + ": cannot be written");
  const Georef g = georef(crs_, centre, b);
  return {{"boundingVolume", {{"region", g.region}}}, {"transform", g.transform}, {"content", {{"uri", uri}}}};
}

json TilesetWriter::leaf(const CellKey& k, const Bounds& b) {
  std::vector<TileBuilding> buildings;
  exp::read_records(spool_of(k, ""), [&](const std::vector<std::uint8_t>& r) { buildings.push_back(tiles::from_bytes(r)); });
  json tile = content(buildings, b, "tiles/" + name(k) + ".glb");
  tile["geometricError"] = 0;
  return tile;
}

// The parent's own content: the prisms of each cell's largest buildings, the
// same number from every cell, so a far view covers the whole extent. Its
// geometric error is what drawing them instead of the children misses: the
// highest roof relief a prism flattens, or the tallest building left out.
void TilesetWriter::coarse(Node& parent, const std::string& uri) {
  const size_t quota = std::max<size_t>(1, kCoarseBuildings / parent.cells.size());
  // Each cell's largest buildings by ground area: a heap with the smallest on top.
  const auto larger = [](const TileBuilding& a, const TileBuilding& b) { return a.areas[3] > b.areas[3]; };
  std::vector<TileBuilding> buildings;
  double error = 1, left_out = 0;
  for (const CellKey& k : parent.cells) {
    std::vector<TileBuilding> kept;
    exp::read_records(spool_of(k, ".coarse"), [&](const std::vector<std::uint8_t>& r) {
      kept.push_back(tiles::from_bytes(r));
      error = std::max(error, kept.back().relief);
      std::push_heap(kept.begin(), kept.end(), larger);
      if (kept.size() <= quota) return;
      std::pop_heap(kept.begin(), kept.end(), larger);
      left_out = std::max(left_out, kept.back().height);
      kept.pop_back();
    });
    std::move(kept.begin(), kept.end(), std::back_inserter(buildings));
  }
  const json children = parent.tile["children"];
  double below = 0;
  for (const json& c : children) below = std::max(below, c["geometricError"].get<double>());
  parent.tile = content(buildings, parent.bounds, uri);
  parent.tile["children"] = children;
  parent.tile["geometricError"] = std::max({error, left_out, 2 * below});
  parent.tile["refine"] = "REPLACE";
}

// A tile's transform applies to its children too: each tile was given its
// content's frame on the Earth, which becomes relative to its parent's.
void nest_transforms(json& tile, const Eigen::Matrix4d& parent) {
  const std::vector<double> t = tile["transform"].get<std::vector<double>>();
  const Eigen::Matrix4d own = Eigen::Map<const Eigen::Matrix4d>(t.data());  // column-major, as 3D Tiles
  const Eigen::Matrix4d relative = parent.inverse() * own;
  tile["transform"] = std::vector<double>(relative.data(), relative.data() + 16);
  if (tile.contains("children"))
    for (json& c : tile["children"]) nest_transforms(c, own);
}

std::vector<std::string> TilesetWriter::finish() {
  // The tiles of one level of the quadtree, by cell counted from the lowest,
  // so that neighbours meet within as few levels as the extent needs.
  std::map<CellKey, Node> level;
  CellKey first{LONG_MAX, LONG_MAX};
  for (const auto& [k, b] : cells_) first = {std::min(first.first, k.first), std::min(first.second, k.second)};
  for (const auto& [k, b] : cells_) level[{k.first - first.first, k.second - first.second}] = {leaf(k, b), b, {k}};
  // Each level up joins 2 x 2 cells, up to one root over them all.
  for (int depth = 1; level.size() > 1 || (depth == 1 && !level.empty()); ++depth) {
    std::map<CellKey, Node> up;
    for (auto& [k, node] : level) {
      Node& parent = up[{k.first >> 1, k.second >> 1}];
      parent.bounds.extend(node.bounds);
      parent.cells.insert(parent.cells.end(), node.cells.begin(), node.cells.end());
      parent.tile["children"].push_back(std::move(node.tile));
    }
    for (auto& [k, node] : up) coarse(node, "tiles/p" + std::to_string(depth) + "_" + name(k) + ".glb");
    level = std::move(up);
  }
  fs::remove_all(spool_dir());
  if (!level.empty()) nest_transforms(level.begin()->second.tile, Eigen::Matrix4d::Identity());
  json root = level.empty() ? json{{"boundingVolume", {{"region", {0, 0, 0, 0, 0, 0}}}}, {"geometricError", 0}}
                            : level.begin()->second.tile;
  const json tileset{{"asset", {{"version", "1.1"}, {"generator", "cadastre3d"}}},
                     {"geometricError", 2 * root["geometricError"].get<double>()},
                     {"root", root}};
  const std::string path = (fs::path(dir_) / "tileset.json").string();
  std::ofstream out(path);
  out << tileset.dump(1) << "\n";
  if (!out) throw std::runtime_error(path + ": cannot be written");
  std::vector<std::string> written = tiles::write_viewer_page(dir_);
  written.insert(written.begin(), path);
  return written;
}

}  // namespace

std::unique_ptr<ExportWriter> tileset_writer(const BatchModel& header, const std::string& dir) {
  return std::make_unique<TilesetWriter>(header, dir);
}

}  // namespace c3d
