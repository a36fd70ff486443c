// CityJSON 2.0 and CityJSONSeq writers. Vertices are integers with scale kScale
// (0.1 mm: rounding to whole mm would tilt the thinnest faces) and translate =
// frame origin, deduplicated.
//
// Each surface once per LoD (docs/exports.md, "CityJSON"): the primary LoD
// ("2.2", or a fallback's "1.3" / "1.2") is the closed Solid, whose semantic
// surfaces are the elements (element_index, type, areas, sigma, evidence), plus
// a MultiSurface of the same LoD holding what of the elements lies outside the
// solid: roof overhangs (the solid's roof is clipped inside the walls), hanging
// roofs and outer ceilings. Summed by semantic type over the primary LoD, the
// surfaces give the store's element totals; the solid alone is what val3dity
// validates and what the volume is of. The elements are not written a second
// time as their own geometry (that doubled every area) and there are no
// BuildingParts: a roof level is the `roof_level` of a semantic surface. Lower
// LoDs (Building::lower_lods) follow as Solids of lod "1.2" / "1.3" with
// per-type semantic surfaces.
#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <stdexcept>
#include <unordered_map>

#include "core/check/polygon_rules.h"
#include "core/geometry/geometry.h"
#include "ifc_citygml/attributes.h"
#include "ifc_citygml/detail.h"
#include "ifc_citygml/export.h"
#include "ifc_citygml/surfaces.h"

namespace c3d {
namespace {

using nlohmann::json;
constexpr double kScale = kExportGridM;  // m per integer unit of the vertices

std::array<long long, 3> grid(const Vec3& local) {
  return {std::llround(local.x() / kScale), std::llround(local.y() / kScale),
          std::llround(local.z() / kScale)};
}

class Vertices {
 public:
  int index(const Vec3& local) {
    const auto k = grid(local);
    auto [it, fresh] = map_.try_emplace(key(k), int(list_.size()));
    if (fresh) list_.push_back(json::array({k[0], k[1], k[2]}));
    return it->second;
  }
  json take() { return std::move(list_); }

 private:
  static std::string key(const std::array<long long, 3>& k) {
    return std::to_string(k[0]) + ',' + std::to_string(k[1]) + ',' + std::to_string(k[2]);
  }
  std::unordered_map<std::string, int> map_;
  json list_ = json::array();
};

json ring_json(Vertices& v, const Ring3& ring) {
  json r = json::array();
  for (const auto& p : ring) r.push_back(v.index(p));
  return r;
}

json surface_json(Vertices& v, const Face& f) {
  json s = json::array({ring_json(v, f.ring)});
  for (size_t k = 0; k < f.holes.size(); ++k) s.push_back(ring_json(v, exp::hole_oriented(f, k)));
  return s;
}

// The semantic surface objects of one geometry: one per element, and one per
// type for solid faces on no element. The first object of an element in the
// building carries its figures; a later one (an overhang beside its roof's
// part in the solid) only names the element, so no area is counted twice.
class Semantics {
 public:
  Semantics(const Building& b, const std::vector<int>& levels, int level_count, std::set<int>& described)
      : b_(b), levels_(levels), level_count_(level_count), described_(described) {}

  size_t of(const exp::SurfacePiece& p) {
    const int key = p.element >= 0 ? p.element : -1 - int(p.type);
    auto [it, fresh] = slot_.try_emplace(key, surfaces.size());
    if (fresh) surfaces.push_back(p.element >= 0 ? element(size_t(p.element)) : typed(p.type));
    return it->second;
  }
  json surfaces = json::array();

 private:
  static json typed(ElementType t) {
    return {{"type", exp::citygml_surface(t)}, {"is_party_wall", t == ElementType::PartyWall}};
  }
  json element(size_t e) {
    const Element& el = b_.elements[e];
    json s = typed(el.type);
    s["element_index"] = e;
    s["element_type"] = to_string(el.type);
    if (level_count_ > 1) s["roof_level"] = levels_[e];
    if (!described_.insert(int(e)).second) return s;
    s.update({{"area", el.area}, {"area_sigma", el.sigma_area}, {"plan_area", el.plan_area},
              {"slope_deg", el.slope_deg}, {"azimuth_deg", el.azimuth_deg},
              {"support_points", el.support_points}, {"rmse", el.rmse},
              {"wall_evidence", to_string(el.evidence)}});
    return s;
  }
  const Building& b_;
  const std::vector<int>& levels_;
  const int level_count_;
  std::set<int>& described_;
  std::map<int, size_t> slot_;
};

// The primary LoD: the Solid, then the MultiSurface of the element parts outside it.
void primary_geometries(json& geometry, Vertices& v, const Building& b) {
  const exp::BuildingSurfaces s = exp::building_surfaces(b);
  int level_count = 1;
  const std::vector<int> levels = exp::element_levels(b, &level_count);
  std::set<int> described;
  if (!s.solid.empty()) {
    Semantics sem(b, levels, level_count, described);
    json shell = json::array(), values = json::array();
    for (const auto& p : s.solid) shell.push_back(surface_json(v, p.face)), values.push_back(sem.of(p));
    geometry.push_back({{"type", "Solid"}, {"lod", b.lod}, {"boundaries", json::array({shell})},
                        {"semantics", {{"surfaces", sem.surfaces}, {"values", json::array({values})}}}});
  }
  if (s.outside.empty()) return;
  Semantics sem(b, levels, level_count, described);
  json bounds = json::array(), values = json::array();
  for (const auto& p : s.outside) bounds.push_back(surface_json(v, p.face)), values.push_back(sem.of(p));
  geometry.push_back({{"type", "MultiSurface"}, {"lod", b.lod}, {"boundaries", bounds},
                      {"semantics", {{"surfaces", sem.surfaces}, {"values", values}}}});
}

json lower_solid(Vertices& v, const Building& b, const LodShell& l) {
  std::set<int> none;
  std::vector<int> levels;
  Semantics sem(b, levels, 1, none);
  json shell = json::array(), values = json::array();
  for (size_t k = 0; k < l.faces.size(); ++k) {
    exp::SurfacePiece p;
    p.type = k < l.face_types.size() ? l.face_types[k] : ElementType::Wall;
    shell.push_back(surface_json(v, l.faces[k]));
    values.push_back(sem.of(p));
  }
  return {{"type", "Solid"}, {"lod", l.lod}, {"boundaries", json::array({shell})},
          {"semantics", {{"surfaces", sem.surfaces}, {"values", json::array({values})}}}};
}

json building_attributes(const BatchModel& m, const ParcelResult& r, const Building& b) {
  const Parcel* p = exp::parcel_of(m, r);
  BuildingTotals t = totals(b);
  json a = {{"parcel_id", r.parcel_id},
            {"right_type", p ? p->right_type : ""},
            {"parcel_ref", "urn:cadastre3d:la_spatialunit:" + r.parcel_id},
            {"roof_area", t.roof}, {"roof_area_sigma", t.sigma_roof},
            {"wall_area", t.wall}, {"wall_area_sigma", t.sigma_wall},
            {"party_wall_area", t.party_wall}, {"party_wall_area_sigma", t.sigma_party_wall},
            {"ground_area", t.ground}, {"ground_area_sigma", t.sigma_ground},
            {"outer_ceiling_area", t.outer_ceiling},
            {"outer_ceiling_area_sigma", t.sigma_outer_ceiling},
            {"volume", b.volume}, {"measuredHeight", b.ridge_height},
            {"eave_height", b.eave_height}, {"storeysAboveGround", b.storeys},
            {"terrain_z", b.terrain_z}, {"solid_valid", b.solid_valid},
            {"lod", b.lod}, {"lod_note", b.lod_note}};
  const exp::QualityAttributes q = exp::quality_attributes(b, m.frame);
  for (const auto& [k, x] : q.texts) a[k] = x;
  for (const auto& [k, x] : q.numbers) a[k] = x;
  for (const auto& [k, x] : q.counts) a[k] = x;
  return a;
}

json building_object(Vertices& v, const BatchModel& m, const ParcelResult& r, const Building& b) {
  json obj = {{"type", "Building"}, {"attributes", building_attributes(m, r, b)},
              {"geometry", json::array()}};
  primary_geometries(obj["geometry"], v, b);
  for (const auto& l : b.lower_lods)
    if (l.lod != b.lod && !l.faces.empty()) obj["geometry"].push_back(lower_solid(v, b, l));
  return obj;
}

// Bounding box of every face written, on the vertex grid, world coordinates.
json extent(const BatchModel& m) {
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  auto add = [&](const Face& f) {
    for (const auto& p : f.ring) {
      const auto k = grid(p);
      const Vec3 q(k[0] * kScale, k[1] * kScale, k[2] * kScale);
      lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
    }
  };
  for (const auto& r : m.results)
    for (const auto& b : r.buildings) {
      for (const auto& f : b.solid) add(f);
      for (const auto& e : b.elements) for (const auto& f : e.faces) add(f);
      for (const auto& l : b.lower_lods) for (const auto& f : l.faces) add(f);
    }
  if (lo.x() > hi.x()) return json::array({0, 0, 0, 0, 0, 0});
  lo += m.frame.origin, hi += m.frame.origin;
  return json::array({lo.x(), lo.y(), lo.z(), hi.x(), hi.y(), hi.z()});
}

// The CityJSON object without city objects and vertices (the CityJSONSeq header).
json header(const BatchModel& m) {
  const Vec3& t = m.frame.origin;
  json meta = {{"title", "Cadastre3D buildings"}, {"geographicalExtent", extent(m)}};
  if (m.epsg > 0) meta["referenceSystem"] = "https://www.opengis.net/def/crs/EPSG/0/" + std::to_string(m.epsg);
  return {{"type", "CityJSON"}, {"version", "2.0"},
          {"transform", {{"scale", {kScale, kScale, kScale}}, {"translate", {t.x(), t.y(), t.z()}}}},
          {"metadata", meta}, {"CityObjects", json::object()}, {"vertices", json::array()}};
}

std::ofstream open_for_writing(const std::string& path) {
  std::ofstream os(path, std::ios::binary);
  if (!os) throw std::runtime_error(path + ": cannot open for writing");
  return os;
}

}  // namespace

void write_cityjson(const BatchModel& model, const std::string& path) {
  Vertices v;
  json doc = header(model);
  for (const auto& r : model.results)
    for (const auto& b : r.buildings) doc["CityObjects"][b.id] = building_object(v, model, r, b);
  doc["vertices"] = v.take();
  std::ofstream os = open_for_writing(path);
  os << doc.dump();
  if (!os) throw std::runtime_error(path + ": write failed");
}

void write_cityjson_seq(const BatchModel& model, const std::string& path) {
  std::ofstream os = open_for_writing(path);
  os << header(model).dump() << '\n';
  for (const auto& r : model.results)
    for (const auto& b : r.buildings) {
      Vertices v;  // each feature has its own vertices
      json feature = {{"type", "CityJSONFeature"}, {"id", b.id}};
      feature["CityObjects"][b.id] = building_object(v, model, r, b);
      feature["vertices"] = v.take();
      os << feature.dump() << '\n';
      if (!os) throw std::runtime_error(path + ": write failed");
    }
  if (!os) throw std::runtime_error(path + ": write failed");
}

}  // namespace c3d
