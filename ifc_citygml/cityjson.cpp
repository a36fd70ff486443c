// CityJSON 2.0 writer and reader. Vertices are integers with scale kScale (0.1 mm:
// rounding to whole mm would tilt the thinnest faces) and
// translate = frame origin, deduplicated; each building has a MultiSurface (one
// semantic surface object per element, carrying its area attributes) on the
// Building or on its BuildingParts, and a Solid (the closed shell) on the
// Building; both of lod "2" for an LoD 2.2 model, "1.2" for an LoD 1.2 prism and
// "1.3" for LoD 1.3 layers.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <tuple>
#include <unordered_map>

#include "core/error.h"
#include "core/geometry/geometry.h"
#include "core/check/polygon_rules.h"
#include "ifc_citygml/detail.h"
#include "ifc_citygml/export.h"

namespace c3d {
namespace {

using nlohmann::json;
constexpr double kScale = kExportGridM;  // m per integer unit of the vertices

class Vertices {
 public:
  int index(const Vec3& local) {
    std::array<long long, 3> k{std::llround(local.x() / kScale), std::llround(local.y() / kScale),
                               std::llround(local.z() / kScale)};
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

json semantic(const Element& el, size_t index) {
  json s = {{"type", exp::citygml_surface(el.type)},
            {"element_index", index},
            {"element_type", to_string(el.type)},
            {"is_party_wall", el.type == ElementType::PartyWall},
            {"area", el.area},
            {"area_sigma", el.sigma_area},
            {"plan_area", el.plan_area},
            {"slope_deg", el.slope_deg},
            {"azimuth_deg", el.azimuth_deg},
            {"support_points", el.support_points},
            {"rmse", el.rmse},
            {"wall_evidence", to_string(el.evidence)}};
  return s;
}

// The geometry's "lod": "2" for the element model (as written before LoDs
// were told apart), a building's own for a simpler one ("1.2").
std::string lod_of(const Building& b) { return b.lod == "2.2" ? "2" : b.lod; }

// MultiSurface of the elements whose level is `level` (all when level < 0).
json multisurface(Vertices& v, const Building& b, const std::vector<int>& lv, int level) {
  json bounds = json::array(), surfaces = json::array(), values = json::array();
  for (size_t e = 0; e < b.elements.size(); ++e) {
    if (level >= 0 && lv[e] != level) continue;
    surfaces.push_back(semantic(b.elements[e], e));
    for (const auto& f : b.elements[e].faces) {
      bounds.push_back(surface_json(v, f));
      values.push_back(surfaces.size() - 1);
    }
  }
  return {{"type", "MultiSurface"}, {"lod", lod_of(b)}, {"boundaries", bounds},
          {"semantics", {{"surfaces", surfaces}, {"values", values}}}};
}

json solid(Vertices& v, const Building& b) {
  json shell = json::array(), surfaces = json::array(), values = json::array();
  std::map<int, int> by_type;
  for (const auto& f : b.solid) {
    ElementType t = exp::solid_face_type(b, f);
    auto [it, fresh] = by_type.try_emplace(int(t), int(surfaces.size()));
    if (fresh)
      surfaces.push_back({{"type", exp::citygml_surface(t)},
                          {"is_party_wall", t == ElementType::PartyWall}});
    shell.push_back(surface_json(v, f));
    values.push_back(it->second);
  }
  return {{"type", "Solid"}, {"lod", lod_of(b)}, {"boundaries", json::array({shell})},
          {"semantics", {{"surfaces", surfaces}, {"values", json::array({values})}}}};
}

json building_attributes(const BatchModel& m, const ParcelResult& r, const Building& b) {
  const Parcel* p = exp::parcel_of(m, r);
  BuildingTotals t = totals(b);
  return {{"parcel_id", r.parcel_id},
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
}

void add_building(json& objects, Vertices& v, const BatchModel& m, const ParcelResult& r,
                  const Building& b) {
  int levels = 1;
  std::vector<int> lv = exp::element_levels(b, &levels);
  json obj = {{"type", "Building"}, {"attributes", building_attributes(m, r, b)},
              {"geometry", json::array()}};
  if (levels == 1) obj["geometry"].push_back(multisurface(v, b, lv, -1));
  if (!b.solid.empty()) obj["geometry"].push_back(solid(v, b));
  if (levels > 1) {
    obj["children"] = json::array();
    for (int l = 0; l < levels; ++l) {
      std::string pid = b.id + "_part" + std::to_string(l);
      objects[pid] = {{"type", "BuildingPart"},
                      {"parents", json::array({b.id})},
                      {"attributes", {{"roof_level", l}}},
                      {"geometry", json::array({multisurface(v, b, lv, l)})}};
      obj["children"].push_back(pid);
    }
  }
  objects[b.id] = std::move(obj);
}

json extent(const json& verts, const Vec3& t) {
  if (verts.empty()) return json::array({0, 0, 0, 0, 0, 0});
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  for (const auto& p : verts) {
    Vec3 q(p[0].get<long long>() * kScale, p[1].get<long long>() * kScale, p[2].get<long long>() * kScale);
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
  lo += t;
  hi += t;
  return json::array({lo.x(), lo.y(), lo.z(), hi.x(), hi.y(), hi.z()});
}

}  // namespace

void write_cityjson(const BatchModel& model, const std::string& path) {
  Vertices v;
  json objects = json::object();
  for (const auto& r : model.results)
    for (const auto& b : r.buildings) add_building(objects, v, model, r, b);
  const Vec3& t = model.frame.origin;
  json doc = {{"type", "CityJSON"}, {"version", "2.0"},
              {"transform", {{"scale", {kScale, kScale, kScale}}, {"translate", {t.x(), t.y(), t.z()}}}},
              {"CityObjects", std::move(objects)}};
  json verts = v.take();
  json meta = {{"title", "Cadastre3D LoD2 buildings"}, {"geographicalExtent", extent(verts, t)}};
  if (model.epsg > 0)
    meta["referenceSystem"] = "https://www.opengis.net/def/crs/EPSG/0/" + std::to_string(model.epsg);
  doc["metadata"] = meta;
  doc["vertices"] = std::move(verts);
  std::ofstream os(path, std::ios::binary);
  if (!os) throw std::runtime_error(path + ": cannot open for writing");
  os << doc.dump();
  if (!os) throw std::runtime_error(path + ": write failed");
}

// ---- reader ---------------------------------------------------------------

namespace {

struct Reader {
  std::string path;
  std::vector<Vec3> verts;  // local coordinates (relative to translate)

  [[noreturn]] void fail(const std::string& what) const { throw InputError(path, what); }

  Ring3 ring(const json& r) const {
    if (!r.is_array()) fail("ring is not an array");
    Ring3 out;
    for (const auto& i : r) {
      if (!i.is_number_integer()) fail("vertex index is not an integer");
      long long k = i.get<long long>();
      if (k < 0 || size_t(k) >= verts.size())
        fail("vertex index " + std::to_string(k) + " out of range (" +
             std::to_string(verts.size()) + " vertices)");
      out.push_back(verts[size_t(k)]);
    }
    return out;
  }

  Face face(const json& s) const {
    if (!s.is_array() || s.empty()) fail("surface without rings");
    Face f;
    f.ring = ring(s[0]);
    for (size_t k = 1; k < s.size(); ++k) f.holes.push_back(ring(s[k]));
    return f;
  }

  static ElementType type_of(const json& sem) {
    std::string t = sem.value("type", "");
    if (t == "RoofSurface") return ElementType::Roof;
    if (t == "GroundSurface") return ElementType::Ground;
    if (t == "OuterCeilingSurface") return ElementType::OuterCeiling;
    return sem.value("is_party_wall", false) ? ElementType::PartyWall : ElementType::Wall;
  }

  // Elements of a MultiSurface: one per semantic surface object (faces in order).
  using Ordered = std::vector<std::pair<size_t, Element>>;  // element_index, element

  void elements(const json& g, Ordered& els) const {
    const json& bounds = g.at("boundaries");
    const json* sem = g.contains("semantics") ? &g["semantics"] : nullptr;
    std::map<size_t, size_t> slot;  // semantic surface -> els index
    for (size_t i = 0; i < bounds.size(); ++i) {
      size_t s = SIZE_MAX;
      if (sem && sem->at("values").is_array() && i < sem->at("values").size() &&
          sem->at("values")[i].is_number_integer())
        s = sem->at("values")[i].get<size_t>();
      auto it = slot.find(s);
      if (it == slot.end()) {
        Element el;
        size_t order = 100000 + els.size();  // files without element_index keep file order
        if (sem && s < sem->at("surfaces").size()) {
          const json& so = sem->at("surfaces")[s];
          el.type = type_of(so);
          el.area = so.value("area", 0.0);
          el.sigma_area = so.value("area_sigma", 0.0);
          el.plan_area = so.value("plan_area", 0.0);
          el.slope_deg = so.value("slope_deg", 0.0);
          el.azimuth_deg = so.value("azimuth_deg", 0.0);
          el.support_points = so.value("support_points", 0);
          el.rmse = so.value("rmse", 0.0);
          order = so.value("element_index", order);
        }
        it = slot.emplace(s, els.size()).first;
        els.push_back({order, std::move(el)});
      }
      els[it->second].second.faces.push_back(face(bounds[i]));
    }
  }

  // Reads the LoD 2 geometry, or an LoD 1.2 prism's or LoD 1.3 layers' (the
  // building's lod then says so).
  void geometry(const json& g, Building& b, Ordered& els) const {
    const json lj = g.value("lod", json());
    const std::string lod = lj.is_string() ? lj.get<std::string>() : lj.dump();
    if (lod == "1.2" || lod == "1.3") b.lod = lod;
    else if (lod.empty() || lod[0] != '2') return;
    std::string type = g.value("type", "");
    if (type == "MultiSurface" || type == "CompositeSurface") elements(g, els);
    if (type == "Solid" && !g.at("boundaries").empty())
      for (const auto& s : g["boundaries"][0]) b.solid.push_back(face(s));
  }
};

int epsg_of(const json& doc) {
  std::string rs;
  if (doc.contains("metadata")) rs = doc["metadata"].value("referenceSystem", "");
  auto slash = rs.find_last_of("/:");
  if (slash == std::string::npos) return 0;
  try { return std::stoi(rs.substr(slash + 1)); } catch (...) { return 0; }
}

}  // namespace

BatchModel read_cityjson(const std::string& path) {
  std::ifstream is(path, std::ios::binary);
  if (!is) throw InputError(path, "cannot open");
  json doc;
  try { doc = json::parse(is); } catch (const std::exception& e) { throw InputError(path, e.what()); }
  if (doc.value("type", "") != "CityJSON") throw InputError(path, "not a CityJSON file");
  Reader rd{path, {}};
  Vec3 scale(1, 1, 1), translate = Vec3::Zero();
  if (doc.contains("transform")) {
    const auto& t = doc["transform"];
    for (int i = 0; i < 3; ++i) { scale[i] = t["scale"][i]; translate[i] = t["translate"][i]; }
  }
  for (const auto& p : doc.at("vertices"))
    rd.verts.emplace_back(p[0].get<double>() * scale.x(), p[1].get<double>() * scale.y(),
                          p[2].get<double>() * scale.z());
  BatchModel m;
  m.frame.origin = translate;
  m.epsg = epsg_of(doc);
  std::map<std::string, size_t> result_of;
  const json& objs = doc.at("CityObjects");
  for (auto it = objs.begin(); it != objs.end(); ++it) {
    const json& o = it.value();
    if (o.value("type", "") != "Building") continue;
    Building b;
    b.id = it.key();
    const json attrs = o.value("attributes", json::object());
    b.volume = attrs.value("volume", 0.0);
    b.ridge_height = attrs.value("measuredHeight", 0.0);
    b.eave_height = attrs.value("eave_height", 0.0);
    b.storeys = attrs.value("storeysAboveGround", 1);
    b.lod_note = attrs.value("lod_note", "");
    Reader::Ordered els;
    for (const auto& g : o.value("geometry", json::array())) rd.geometry(g, b, els);
    for (const auto& c : o.value("children", json::array())) {
      std::string cid = c.get<std::string>();
      if (!objs.contains(cid)) throw InputError(path, "child " + cid + " of " + b.id + " missing");
      for (const auto& g : objs[cid].value("geometry", json::array())) rd.geometry(g, b, els);
    }
    std::stable_sort(els.begin(), els.end(),
                     [](const auto& x, const auto& y) { return x.first < y.first; });
    for (auto& [order, el] : els) {
      if (el.area == 0) for (const auto& f : el.faces) el.area += area(f);
      b.elements.push_back(std::move(el));
    }
    std::string pid = attrs.value("parcel_id", "");
    auto [slot, fresh] = result_of.try_emplace(pid, m.results.size());
    if (fresh) {
      Parcel p;
      p.index = int(m.parcels.size());
      p.id = pid;
      p.right_type = attrs.value("right_type", "");
      m.parcels.push_back(p);
      ParcelResult r;
      r.parcel_index = p.index;
      r.parcel_id = pid;
      r.status = ParcelStatus::Ok;
      m.results.push_back(r);
    }
    m.results[slot->second].buildings.push_back(std::move(b));
  }
  return m;
}

}  // namespace c3d
