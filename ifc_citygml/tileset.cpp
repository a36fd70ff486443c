// 3D Tiles 1.1 of a batch (`--formats 3dtiles`, docs/exports.md "3D Tiles"):
// OUT/3dtiles/tileset.json and one glTF content tile per cell of kCellM
// metres, under a quadtree of the cells. Pages are spooled per cell as they
// come, so the writer holds one cell at a time and the cells' bounds.
#include <algorithm>
#include <climits>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "core/geometry/geometry.h"
#include "core/io/crs.h"
#include "ifc_citygml/detail.h"
#include "ifc_citygml/export.h"
#include "ifc_citygml/tile_content.h"
#include "valuation/valuation_types.h"

namespace c3d {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using tiles::TileBuilding;
using tiles::TileElement;

constexpr double kCellM = 250;  // a content tile's side: a few hundred buildings in a town

using CellKey = std::pair<long, long>;

struct Bounds {
  Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
  void add(const Vec3& p) { lo = lo.cwiseMin(p), hi = hi.cwiseMax(p); }
  void add(const Bounds& b) { add(b.lo), add(b.hi); }
};

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
    const double x = b.lo.x() + t * (b.hi.x() - b.lo.x()), y = b.lo.y() + t * (b.hi.y() - b.lo.y());
    rim.insert(rim.end(), {Vec3(x, b.lo.y(), 0), Vec3(x, b.hi.y(), 0), Vec3(b.lo.x(), y, 0), Vec3(b.hi.x(), y, 0)});
  }
  reproject_points(rim, crs, wkt_from_epsg(4979), "3dtiles");
  Bounds ll;
  for (const Vec3& p : rim) ll.add(p * (M_PI / 180));
  constexpr double kMarginRad = 1e-8;  // 6 cm: the samples between the corners
  g.region = {ll.lo.x() - kMarginRad, ll.lo.y() - kMarginRad, ll.hi.x() + kMarginRad, ll.hi.y() + kMarginRad,
              b.lo.z(), b.hi.z()};
  return g;
}

json region_union(const json& a, const json& b) {
  return json::array({std::min(a[0].get<double>(), b[0].get<double>()), std::min(a[1].get<double>(), b[1].get<double>()),
                      std::max(a[2].get<double>(), b[2].get<double>()), std::max(a[3].get<double>(), b[3].get<double>()),
                      std::min(a[4].get<double>(), b[4].get<double>()), std::max(a[5].get<double>(), b[5].get<double>())});
}

// A building's record in a cell's spool, and back.
json record(const TileBuilding& b) {
  json es = json::array();
  for (const TileElement& e : b.elements) {
    json faces = json::array();
    for (const auto& f : e.faces) {
      std::vector<double> flat;
      for (const Vec3& v : f) flat.insert(flat.end(), {v.x(), v.y(), v.z()});
      faces.push_back(flat);
    }
    es.push_back({{"t", int(e.type)}, {"a", e.area}, {"sa", e.sigma_area}, {"pa", e.plan_area}, {"sl", e.slope_deg},
                  {"r", e.rmse}, {"n", e.support_points}, {"m", e.amount}, {"f", faces}});
  }
  return {{"b", b.building_id}, {"p", b.parcel_id}, {"s", b.status}, {"l", b.lod}, {"c", b.currency},
          {"a", b.areas}, {"v", {b.building_value, b.njop, b.njop_per_m2, b.tax}}, {"e", es}};
}

TileBuilding from_record(const json& j) {
  TileBuilding b;
  b.building_id = j["b"], b.parcel_id = j["p"], b.status = j["s"], b.lod = j["l"], b.currency = j["c"];
  b.areas = j["a"].get<std::array<double, 6>>();
  const auto v = j["v"].get<std::array<double, 4>>();
  b.building_value = v[0], b.njop = v[1], b.njop_per_m2 = v[2], b.tax = v[3];
  for (const json& je : j["e"]) {
    TileElement e;
    e.type = ElementType(je["t"].get<int>());
    e.area = je["a"], e.sigma_area = je["sa"], e.plan_area = je["pa"], e.slope_deg = je["sl"];
    e.rmse = je["r"], e.support_points = je["n"], e.amount = je["m"];
    for (const json& jf : je["f"]) {
      const auto flat = jf.get<std::vector<double>>();
      std::vector<Vec3> face;
      for (size_t i = 0; i + 2 < flat.size(); i += 3) face.emplace_back(flat[i], flat[i + 1], flat[i + 2]);
      e.faces.push_back(std::move(face));
    }
    b.elements.push_back(std::move(e));
  }
  return b;
}

// Element i's cost amount in the parcel's valuation (-1 where it has none).
double element_amount(const ParcelValuation* v, const std::string& building, int i) {
  if (!v) return -1;
  for (const CostItem& c : v->items)
    if (c.building_id == building && c.element_index == i) return c.amount;
  return -1;
}

TileBuilding tile_building(const Building& b, const ParcelResult& r, const ParcelValuation* v, const LocalFrame& f) {
  TileBuilding t;
  t.building_id = b.id, t.parcel_id = r.parcel_id, t.status = to_string(r.status), t.lod = to_string(b.lod);
  const BuildingTotals s = totals(b);
  t.areas = {s.roof, s.wall, s.party_wall, s.ground, s.outer_ceiling, b.volume};
  if (v) {
    t.currency = v->currency, t.building_value = v->building_value, t.njop = v->njop, t.tax = v->tax;
    if (v->land_area > 0) t.njop_per_m2 = v->njop / v->land_area;
  }
  for (size_t i = 0; i < b.elements.size(); ++i) {
    const Element& el = b.elements[i];
    TileElement e;
    e.type = el.type, e.area = el.area, e.sigma_area = el.sigma_area, e.plan_area = el.plan_area;
    e.slope_deg = el.slope_deg, e.rmse = el.rmse, e.support_points = el.support_points;
    e.amount = element_amount(v, b.id, int(i));
    for (const Face& face : el.faces) {
      const exp::Triangles tri = exp::triangulate(face);
      std::vector<Vec3> soup;
      for (const auto& k : tri.tris)
        for (int j : k) soup.push_back(f.to_world(tri.points[size_t(j)]));
      e.faces.push_back(std::move(soup));
    }
    t.elements.push_back(std::move(e));
  }
  return t;
}

class TilesetWriter : public ExportWriter {
 public:
  TilesetWriter(const BatchModel& header, const std::string& dir) : crs_(header.crs_wkt), dir_(dir) {
    if (crs_.empty())
      throw std::runtime_error(dir + ": 3D Tiles need the batch's CRS to place the buildings on the Earth; it has none");
    fs::create_directories(fs::path(dir) / "tiles");
    fs::create_directories(spool_dir());
  }
  void values(const std::vector<ParcelValuation>& v) override { values_ = v; }
  void add(const BatchModel& page) override {
    for (const ParcelResult& r : page.results) {
      const ParcelValuation* v = nullptr;
      for (const auto& x : values_)
        if (x.parcel_id == r.parcel_id) v = &x;
      for (const Building& b : r.buildings) spool(tile_building(b, r, v, page.frame));
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
  std::string spool_of(const CellKey& k) const { return (fs::path(spool_dir()) / (name(k) + ".msgpack")).string(); }

  void spool(const TileBuilding& b) {
    Bounds box;
    for (const auto& e : b.elements)
      for (const auto& f : e.faces)
        for (const Vec3& p : f) box.add(p);
    if (!(box.lo.x() <= box.hi.x())) return;  // no faces
    const Vec3 mid = (box.lo + box.hi) / 2;
    const CellKey k{long(std::floor(mid.x() / kCellM)), long(std::floor(mid.y() / kCellM))};
    cells_[k].add(box);
    const std::vector<std::uint8_t> bytes = json::to_msgpack(record(b));
    const std::uint64_t n = bytes.size();
    std::ofstream out(spool_of(k), std::ios::binary | std::ios::app);
    out.write(reinterpret_cast<const char*>(&n), sizeof n);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(n));
    if (!out) throw std::runtime_error(spool_of(k) + ": cannot be written");
  }
  json leaf(const CellKey& k, const Bounds& b);
};

json TilesetWriter::leaf(const CellKey& k, const Bounds& b) {
  std::vector<TileBuilding> buildings;
  std::ifstream in(spool_of(k), std::ios::binary);
  std::uint64_t n = 0;
  while (in.read(reinterpret_cast<char*>(&n), sizeof n)) {
    std::vector<std::uint8_t> bytes(n);
    in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(n));
    buildings.push_back(from_record(json::from_msgpack(bytes)));
  }
  const Vec3 centre((b.lo.x() + b.hi.x()) / 2, (b.lo.y() + b.hi.y()) / 2, b.lo.z());
  const std::vector<unsigned char> glb = tiles::tile_glb(buildings, centre);
  const std::string uri = "tiles/" + name(k) + ".glb";
  std::ofstream out(fs::path(dir_) / uri, std::ios::binary);
  out.write(reinterpret_cast<const char*>(glb.data()), std::streamsize(glb.size()));
  if (!out) throw std::runtime_error((fs::path(dir_) / uri).string() + ": cannot be written");
  const Georef g = georef(crs_, centre, b);
  return {{"boundingVolume", {{"region", g.region}}},
          {"geometricError", 0},
          {"transform", g.transform},
          {"content", {{"uri", uri}}}};
}

std::vector<std::string> TilesetWriter::finish() {
  // The tiles of one level of the quadtree, by cell counted from the lowest,
  // so that neighbours meet within as few levels as the extent needs.
  std::map<CellKey, json> level;
  CellKey first{LONG_MAX, LONG_MAX};
  for (const auto& [k, b] : cells_) first = {std::min(first.first, k.first), std::min(first.second, k.second)};
  for (const auto& [k, b] : cells_) level[{k.first - first.first, k.second - first.second}] = leaf(k, b);
  fs::remove_all(spool_dir());
  // Each level up joins 2 x 2 cells; a tile's error is its cell's side,
  // what is lost when its children are not drawn.
  double side = kCellM;
  while (level.size() > 1 || (!level.empty() && level.begin()->second.contains("content"))) {
    std::map<CellKey, json> up;
    for (auto& [k, tile] : level) {
      json& parent = up[{k.first >> 1, k.second >> 1}];
      const json region = tile["boundingVolume"]["region"];
      parent["boundingVolume"]["region"] =
          parent.contains("boundingVolume") ? region_union(parent["boundingVolume"]["region"], region) : region;
      parent["geometricError"] = 2 * side;
      parent["refine"] = "ADD";
      parent["children"].push_back(std::move(tile));
    }
    level = std::move(up);
    side *= 2;
  }
  json root = level.empty() ? json{{"boundingVolume", {{"region", {0, 0, 0, 0, 0, 0}}}}, {"geometricError", 0}}
                            : level.begin()->second;
  const json tileset{{"asset", {{"version", "1.1"}, {"generator", "cadastre3d"}}},
                     {"geometricError", root["geometricError"]},
                     {"root", root}};
  const std::string path = (fs::path(dir_) / "tileset.json").string();
  std::ofstream out(path);
  out << tileset.dump(1) << "\n";
  if (!out) throw std::runtime_error(path + ": cannot be written");
  return {path};
}

}  // namespace

std::unique_ptr<ExportWriter> tileset_writer(const BatchModel& header, const std::string& dir) {
  return std::make_unique<TilesetWriter>(header, dir);
}

}  // namespace c3d
