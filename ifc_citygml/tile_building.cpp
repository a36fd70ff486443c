#include "ifc_citygml/tile_building.h"

#include <map>
#include <tuple>

#include <nlohmann/json.hpp>

#include "core/geometry/geometry.h"
#include "ifc_citygml/detail.h"
#include "valuation/valuation_types.h"

namespace c3d::tiles {

using nlohmann::json;

namespace {

// A face's triangles in world coordinates, vertex by vertex.
std::vector<Vec3> triangles_of(const Face& face, const LocalFrame& f) {
  const exp::Triangles tri = exp::triangulate(face);
  std::vector<Vec3> soup;
  for (const auto& k : tri.tris)
    for (int j : k) soup.push_back(f.to_world(tri.points[size_t(j)]));
  return soup;
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
          {"a", b.areas}, {"v", {b.building_value, b.njop, b.njop_per_m2, b.tax}}, {"h", {b.height, b.relief}},
          {"e", es}};
}

TileBuilding from_record(const json& j) {
  TileBuilding b;
  b.building_id = j["b"], b.parcel_id = j["p"], b.status = j["s"], b.lod = j["l"], b.currency = j["c"];
  b.areas = j["a"].get<std::array<double, 6>>();
  const auto v = j["v"].get<std::array<double, 4>>();
  b.building_value = v[0], b.njop = v[1], b.njop_per_m2 = v[2], b.tax = v[3];
  const auto h = j["h"].get<std::array<double, 2>>();
  b.height = h[0], b.relief = h[1];
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

}  // namespace

TileBuilding tile_building(const Building& b, const ParcelResult& r, const ParcelValuation* v, const LocalFrame& f) {
  TileBuilding t;
  t.building_id = b.id, t.parcel_id = r.parcel_id, t.status = to_string(r.status), t.lod = to_string(b.lod);
  const BuildingTotals s = totals(b);
  t.areas = {s.roof, s.wall, s.party_wall, s.ground, s.outer_ceiling, b.volume};
  t.height = b.ridge_height, t.relief = b.ridge_height - b.eave_height;
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
    for (const Face& face : el.faces) e.faces.push_back(triangles_of(face, f));
    t.elements.push_back(std::move(e));
  }
  return t;
}

TileBuilding coarse_building(const Building& b, const TileBuilding& full, const LocalFrame& f) {
  const LodShell* prism = lower_lod(b, Lod::Lod12);
  if (!prism) return full;
  TileBuilding t = full;
  t.elements.clear();
  const BuildingTotals s = totals(b);
  const std::map<ElementType, std::pair<double, double>> total{  // area, sigma
      {ElementType::Roof, {s.roof, s.sigma_roof}},
      {ElementType::Wall, {s.wall, s.sigma_wall}},
      {ElementType::PartyWall, {s.party_wall, s.sigma_party_wall}},
      {ElementType::Ground, {s.ground, s.sigma_ground}},
      {ElementType::OuterCeiling, {s.outer_ceiling, s.sigma_outer_ceiling}}};
  std::map<ElementType, TileElement> by_type;
  for (const TileElement& e : full.elements) {
    TileElement& sum = by_type[e.type];
    sum.type = e.type;
    sum.plan_area += e.plan_area, sum.support_points += e.support_points;
    sum.amount = e.amount < 0 ? sum.amount : std::max(0.0, sum.amount) + e.amount;
  }
  for (auto& [type, e] : by_type) {
    std::tie(e.area, e.sigma_area) = total.at(type);
    e.slope_deg = -1, e.rmse = -1;
  }
  for (size_t i = 0; i < prism->faces.size(); ++i) {
    TileElement& e = by_type[prism->face_types[i]];
    e.type = prism->face_types[i];
    e.faces.push_back(triangles_of(prism->faces[i], f));
  }
  for (auto& [type, e] : by_type)
    if (!e.faces.empty()) t.elements.push_back(std::move(e));
  return t;
}

std::vector<std::uint8_t> to_bytes(const TileBuilding& b) { return json::to_msgpack(record(b)); }
TileBuilding from_bytes(const std::vector<std::uint8_t>& bytes) { return from_record(json::from_msgpack(bytes)); }

}  // namespace c3d::tiles
