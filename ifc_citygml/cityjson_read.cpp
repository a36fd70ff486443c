// CityJSON reader: our export (the primary LoD's Solid and its MultiSurface of
// element parts outside it, lower LoDs as further Solids) and files of the
// earlier layout (element MultiSurfaces on the Building or its BuildingParts
// beside a Solid of per-type semantics), or any CityJSON 2.0 Buildings.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <stdexcept>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/geometry/geometry.h"
#include "ifc_citygml/export.h"

namespace c3d {
namespace {

using nlohmann::json;

ElementType type_of(const json& sem) {
  std::string t = sem.value("type", "");
  if (t == "RoofSurface") return ElementType::Roof;
  if (t == "GroundSurface") return ElementType::Ground;
  if (t == "OuterCeilingSurface") return ElementType::OuterCeiling;
  return sem.value("is_party_wall", false) ? ElementType::PartyWall : ElementType::Wall;
}

std::string lod_of(const json& g) {
  const json lj = g.value("lod", json());
  std::string lod = lj.is_string() ? lj.get<std::string>() : lj.dump();
  return lod == "2" ? "2.2" : lod;  // files before LoDs were told apart
}

double lod_number(const std::string& lod) {
  try { return std::stod(lod); } catch (...) { return -1; }
}

struct Reader {
  std::string path;
  std::vector<Vec3> verts;  // local coordinates (relative to translate)

  [[noreturn]] void fail(const std::string& what) const { throw InputError(path, what); }

  Lod lod(const std::string& text) const {
    try {
      return lod_from(text);
    } catch (const std::invalid_argument& e) {
      fail(e.what());
    }
  }

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

  // Elements keyed by element_index; surfaces without one get their own key
  // (after every indexed one, in file order).
  using Elements = std::map<size_t, Element>;

  static void describe(Element& el, const json& so) {
    el.type = type_of(so);
    if (!so.contains("area")) return;  // a later part of an element already described
    el.area = so.value("area", 0.0);
    el.sigma_area = so.value("area_sigma", 0.0);
    el.plan_area = so.value("plan_area", 0.0);
    el.slope_deg = so.value("slope_deg", 0.0);
    el.azimuth_deg = so.value("azimuth_deg", 0.0);
    el.support_points = so.value("support_points", 0);
    el.rmse = so.value("rmse", 0.0);
  }

  // Faces of one primary-LoD surface list (a MultiSurface, or a Solid's shell)
  // into elements; a Solid's faces whose surface names no element (per-type
  // semantics) make no element.
  void elements(const json& bounds, const json* surfaces, const json* values, bool solid,
                size_t geom, Elements& els) const {
    constexpr size_t kUnindexed = 1000000000, kPerGeometry = 1000000;  // after every element_index
    for (size_t i = 0; i < bounds.size(); ++i) {
      size_t s = SIZE_MAX;
      if (surfaces && values && i < values->size() && (*values)[i].is_number_integer() &&
          (*values)[i].get<size_t>() < surfaces->size())
        s = (*values)[i].get<size_t>();
      const json* so = s == SIZE_MAX ? nullptr : &(*surfaces)[s];
      size_t key;
      if (so && so->contains("element_index")) key = so->at("element_index").get<size_t>();
      else if (solid) continue;
      else key = kUnindexed + geom * kPerGeometry + std::min(s, kPerGeometry - 1);
      auto [it, fresh] = els.try_emplace(key);
      if (fresh) it->second.type = so ? type_of(*so) : ElementType::Wall;
      if (so) describe(it->second, *so);
      it->second.faces.push_back(face(bounds[i]));
    }
  }

  LodShell lower(const json& g, const std::string& text) const {
    LodShell l;
    l.lod = lod(text);
    const json& shell = g.at("boundaries").at(0);
    const json* sem = g.contains("semantics") ? &g["semantics"] : nullptr;
    for (size_t i = 0; i < shell.size(); ++i) {
      l.faces.push_back(face(shell[i]));
      ElementType t = ElementType::Wall;
      if (sem && sem->at("values").at(0).at(i).is_number_integer())
        t = type_of(sem->at("surfaces").at(sem->at("values")[0][i].get<size_t>()));
      l.face_types.push_back(t);
    }
    return l;
  }

  // The geometries of a building (its own and its BuildingParts'): the highest
  // LoD gives the elements and the solid, lower Solids the lower LoDs.
  void building(const std::vector<const json*>& geoms, Building& b) const {
    double top = -1;
    for (const json* g : geoms) top = std::max(top, lod_number(lod_of(*g)));
    Elements els;
    for (size_t gi = 0; gi < geoms.size(); ++gi) {
      const json* g = geoms[gi];
      const std::string text = lod_of(*g), type = g->value("type", "");
      const json* sem = g->contains("semantics") ? &(*g)["semantics"] : nullptr;
      const json* surfaces = sem ? &sem->at("surfaces") : nullptr;
      if (lod_number(text) < top) {
        if (type == "Solid" && !g->at("boundaries").empty()) b.lower_lods.push_back(lower(*g, text));
        continue;
      }
      b.lod = lod(text);
      if (type == "MultiSurface" || type == "CompositeSurface")
        elements(g->at("boundaries"), surfaces, sem ? &sem->at("values") : nullptr, false, gi, els);
      if (type == "Solid" && !g->at("boundaries").empty()) {
        const json& shell = g->at("boundaries")[0];
        for (const auto& s : shell) b.solid.push_back(face(s));
        elements(shell, surfaces, sem ? &sem->at("values").at(0) : nullptr, true, gi, els);
      }
    }
    std::sort(b.lower_lods.begin(), b.lower_lods.end(),
              [](const LodShell& x, const LodShell& y) { return x.lod < y.lod; });
    for (auto& [key, el] : els) {
      if (el.area == 0) for (const auto& f : el.faces) el.area += area(f);
      b.elements.push_back(std::move(el));
    }
  }
};

int epsg_of(const json& doc) {
  std::string rs;
  if (doc.contains("metadata")) rs = doc["metadata"].value("referenceSystem", "");
  auto slash = rs.find_last_of("/:");
  if (slash == std::string::npos) return 0;
  try { return std::stoi(rs.substr(slash + 1)); } catch (...) { return 0; }
}

double number_or_nan(const json& attrs, const char* key, double offset) {
  const auto it = attrs.find(key);
  return it != attrs.end() && it->is_number() ? it->get<double>() - offset : kNaN;
}

// Building attributes as write_cityjson names them (heights back to local z).
void read_attributes(const json& attrs, double z0, Building& b) {
  b.volume = attrs.value("volume", 0.0);
  b.ridge_height = attrs.value("measuredHeight", 0.0);
  b.eave_height = attrs.value("eave_height", 0.0);
  b.storeys = attrs.value("storeysAboveGround", 1);
  b.lod_note = attrs.value("lod_note", "");
  b.terrain_z = attrs.value("terrain_z", 0.0);
  BuildingAttributes& a = b.attributes;
  a.roof_type = attrs.value("roof_type", "");
  a.roof_z_min = number_or_nan(attrs, "roof_height_min", z0);
  a.roof_z_50p = number_or_nan(attrs, "roof_height_50p", z0);
  a.roof_z_70p = number_or_nan(attrs, "roof_height_70p", z0);
  a.roof_z_max = number_or_nan(attrs, "roof_height_max", z0);
  a.roof_points = attrs.value("roof_points", 0L);
  a.point_density = number_or_nan(attrs, "point_density", 0);
  a.data_quality = attrs.value("data_quality", "");
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
    read_attributes(attrs, translate.z(), b);
    std::vector<const json*> geoms;  // pointers into doc
    auto gather = [&](const json& obj) {
      if (obj.contains("geometry") && obj["geometry"].is_array())
        for (const auto& g : obj["geometry"]) geoms.push_back(&g);
    };
    gather(o);
    for (const auto& c : o.value("children", json::array())) {
      std::string cid = c.get<std::string>();
      if (!objs.contains(cid)) throw InputError(path, "child " + cid + " of " + b.id + " missing");
      gather(objs[cid]);
    }
    try { rd.building(geoms, b); } catch (const json::exception& e) { throw InputError(path, b.id + ": " + e.what()); }
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
