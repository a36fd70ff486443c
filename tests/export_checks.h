#pragma once
// The independent checks of the export files, shared by the per-format tests and
// the Cimahi acceptance test: CityGML schema (xmllint) and xlinks, CityJSON schema
// (ajv) and vertex indices, IFC read back strictly by IFC++ and by web-ifc.
// Each tool is optional on a developer machine; can_*() says whether it is there.
#include <algorithm>
#include <functional>
#include <gtest/gtest.h>
#include <iostream>
#include <sstream>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "core/geometry/geometry.h"
#include "core/types.h"
#include "tests/export_fixtures.h"
#include "tests/test_support.h"

#ifdef C3D_HAVE_IFCPP
#include <ifcpp/IFC4/include/IfcAreaMeasure.h>
#include <ifcpp/IFC4/include/IfcBoolean.h>
#include <ifcpp/IFC4/include/IfcBuilding.h>
#include <ifcpp/IFC4/include/IfcBuildingStorey.h>
#include <ifcpp/IFC4/include/IfcElement.h>
#include <ifcpp/IFC4/include/IfcElementQuantity.h>
#include <ifcpp/IFC4/include/IfcIdentifier.h>
#include <ifcpp/IFC4/include/IfcLabel.h>
#include <ifcpp/IFC4/include/IfcPropertySet.h>
#include <ifcpp/IFC4/include/IfcPropertySingleValue.h>
#include <ifcpp/IFC4/include/IfcQuantityArea.h>
#include <ifcpp/IFC4/include/IfcRelAggregates.h>
#include <ifcpp/IFC4/include/IfcRelContainedInSpatialStructure.h>
#include <ifcpp/IFC4/include/IfcRelDefinesByProperties.h>
#include <ifcpp/IFC4/include/IfcRoof.h>
#include <ifcpp/model/BuildingModel.h>
#include <ifcpp/reader/ReaderSTEP.h>
#endif

namespace c3d::check {

// Every xlink:href="#id" names an existing gml:id; returns the ones that do not.
inline std::vector<std::string> dangling_xlinks(const std::string& xml) {
  std::set<std::string> ids;
  std::regex id_re("gml:id=\"([^\"]+)\"");
  for (std::sregex_iterator it(xml.begin(), xml.end(), id_re), end; it != end; ++it)
    ids.insert((*it)[1]);
  std::vector<std::string> bad;
  std::regex href_re("xlink:href=\"#([^\"]+)\"");
  for (std::sregex_iterator it(xml.begin(), xml.end(), href_re), end; it != end; ++it)
    if (!ids.count((*it)[1])) bad.push_back((*it)[1]);
  return bad;
}

inline bool can_xmllint() {
  return fixture::have_program("xmllint") && !test::schemas_dir().empty();
}

// Schema check against the CityGML 2.0 or 3.0 XSDs of ../shared/schemas.
inline int xmllint(const std::string& file, std::string* out, int version = 2) {
  std::string xsd = test::schemas_dir() + "/citygml/citygml" + std::to_string(version) + "-all.xsd";
  return fixture::sh("xmllint --nonet --noout --schema " + xsd + " " + file, out);
}

// Element areas from a CityGML 2.0 or 3.0 file: "<building>/e<k>" -> the area
// generic attribute of the boundary surface gml:id="c3d_<building>_e<k>".
inline std::map<std::string, double> citygml_areas(const std::string& xml) {
  std::regex surf_re(
      "<(?:bldg|con):\\w+Surface gml:id=\"c3d_([^\"]+)_e(\\d+)\">[\\s\\S]*?"
      "(?:<gen:doubleAttribute name=\"area\">|<gen:name>area</gen:name>)<gen:value>([0-9.]+)</gen:value>");
  std::map<std::string, double> read;
  for (std::sregex_iterator it(xml.begin(), xml.end(), surf_re), end; it != end; ++it)
    read[(*it)[1].str() + "/e" + (*it)[2].str()] = std::stod((*it)[3]);
  return read;
}

// Area of every gml:Polygon of a CityGML file by its gml:id (exterior minus
// interiors; an xlink to a polygon is no polygon of its own).
inline std::map<std::string, double> citygml_polygon_areas(const std::string& xml) {
  std::map<std::string, double> out;
  const std::regex poly_re("<gml:Polygon gml:id=\"([^\"]+)\">([\\s\\S]*?)</gml:Polygon>");
  const std::regex pos_re("<gml:posList[^>]*>([^<]*)</gml:posList>");
  for (std::sregex_iterator it(xml.begin(), xml.end(), poly_re), end; it != end; ++it) {
    const std::string body = (*it)[2];
    Face f;
    for (std::sregex_iterator jt(body.begin(), body.end(), pos_re); jt != end; ++jt) {
      std::istringstream in((*jt)[1].str());
      Ring3 ring;
      for (double x, y, z; in >> x >> y >> z;) ring.emplace_back(x, y, z);
      ring.pop_back();  // GML repeats the first point
      if (f.ring.empty()) f.ring = ring;
      else f.holes.push_back(ring);
    }
    out[(*it)[1]] = area(f);
  }
  return out;
}

// Boundary indices outside [0, vertices): the CityJSON schema cannot see them.
inline size_t bad_indices(const nlohmann::json& doc) {
  const long long n = doc["vertices"].size();
  size_t bad = 0;
  std::function<void(const nlohmann::json&)> walk = [&](const nlohmann::json& j) {
    if (j.is_array()) for (const auto& x : j) walk(x);
    else if (!j.is_number_integer() || j.get<long long>() < 0 || j.get<long long>() >= n) ++bad;
  };
  for (const auto& [id, obj] : doc["CityObjects"].items())
    for (const auto& g : obj.value("geometry", nlohmann::json::array())) walk(g["boundaries"]);
  return bad;
}

// Area of every surface at each city object's highest LoD, summed over the
// file by semantic surface type ("WallSurface/party" for a party wall), as a
// GIS user sums a layer: every geometry of that LoD, polygons minus holes.
inline std::map<std::string, double> cityjson_type_areas(const nlohmann::json& doc) {
  std::vector<Vec3> v;
  const auto& t = doc["transform"];
  for (const auto& p : doc["vertices"])
    v.emplace_back(p[0].get<double>() * t["scale"][0].get<double>(), p[1].get<double>() * t["scale"][1].get<double>(),
                   p[2].get<double>() * t["scale"][2].get<double>());
  std::map<std::string, double> sum;
  auto add = [&](const nlohmann::json& surface, const nlohmann::json& so) {
    Face f;
    for (size_t r = 0; r < surface.size(); ++r) {
      Ring3 ring;
      for (const auto& i : surface[r]) ring.push_back(v.at(i.get<size_t>()));
      if (r == 0) f.ring = ring;
      else f.holes.push_back(ring);
    }
    sum[so["type"].get<std::string>() + (so.value("is_party_wall", false) ? "/party" : "")] += area(f);
  };
  for (const auto& [id, obj] : doc["CityObjects"].items()) {
    double top = -1;
    for (const auto& g : obj.value("geometry", nlohmann::json::array())) top = std::max(top, std::stod(g["lod"].get<std::string>()));
    for (const auto& g : obj.value("geometry", nlohmann::json::array())) {
      if (std::stod(g["lod"].get<std::string>()) != top) continue;
      const auto& sem = g["semantics"];
      const bool solid = g["type"] == "Solid";
      const auto& bounds = solid ? g["boundaries"][0] : g["boundaries"];
      const auto& values = solid ? sem["values"][0] : sem["values"];
      for (size_t k = 0; k < bounds.size(); ++k) add(bounds[k], sem["surfaces"][values[k].get<size_t>()]);
    }
  }
  return sum;
}

// The same names for the store's element totals.
inline std::map<std::string, double> store_type_areas(const BatchModel& m) {
  std::map<std::string, double> sum;
  for (const auto& r : m.results)
    for (const auto& b : r.buildings)
      for (const auto& e : b.elements) {
        std::string name = e.type == ElementType::Roof ? "RoofSurface"
                           : e.type == ElementType::Ground ? "GroundSurface"
                           : e.type == ElementType::OuterCeiling ? "OuterCeilingSurface"
                                                                 : "WallSurface";
        sum[name + (e.type == ElementType::PartyWall ? "/party" : "")] += e.area;
      }
  return sum;
}

// Buildings `cadastre3d validate FILE` finds issues with (ids from its lines).
inline std::set<std::string> validate_invalid(const std::string& file, std::string* log) {
  test::run_cli("validate " + file, log);
  std::set<std::string> ids;
  std::istringstream in(*log);
  for (std::string line; std::getline(in, line);)
    if (line.rfind("validate: ", 0) != 0 && line.find(": ") != std::string::npos)
      ids.insert(line.substr(0, line.find(": ")));
  return ids;
}

// val3dity finds every building of a CityJSON (or CityJSONSeq) file valid,
// and `cadastre3d validate` reaches the same verdict on each building of a
// CityJSON file; without val3dity beside the checkout, says so and checks ours.
inline void expect_judges_agree(const std::string& cityjson) {
  std::string log;
  const bool seq = cityjson.size() > 6 && cityjson.substr(cityjson.size() - 6) == ".jsonl";
  const std::set<std::string> ours = seq ? std::set<std::string>{} : validate_invalid(cityjson, &log);
  const auto judged = test::val3dity_invalid(cityjson);
  if (!judged) {
    test::note_missing("val3dity not found beside the checkout: " + cityjson + " judged by our check only");
    EXPECT_TRUE(ours.empty()) << log;
    return;
  }
  const std::set<std::string> val3dity(judged->begin(), judged->end());
  std::string ids;
  for (const auto& id : val3dity) ids += " " + id;
  EXPECT_TRUE(val3dity.empty()) << cityjson << ": val3dity finds invalid:" << ids;
  if (!seq) EXPECT_EQ(ours, val3dity) << cityjson << ": cadastre3d validate disagrees\n" << log;
}

inline bool can_ajv() { return !fixture::js_dir().empty() && !test::schemas_dir().empty(); }

// schema: "cityjson" or "cityjsonfeature" (a CityJSONSeq line) of CityJSON 2.0.2.
inline int ajv(const std::string& file, std::string* out, const std::string& schema_name = "cityjson") {
  std::string schema = test::schemas_dir() + "/cityjson/2.0.2/" + schema_name + ".min.schema.json";
  return fixture::sh("cd " + fixture::js_dir() +
                         " && node_modules/.bin/ajv validate --spec=draft7 -c ajv-formats --strict=false -s " +
                         schema + " -d " + file,
                     out);
}

inline bool can_web_ifc() { return !fixture::js_dir().empty(); }

// web-ifc's reading (tests/js/ifc_check.js): {elements: [{type, tag, meshes,
// triangles, mesh_area}], quantities: [{tag, name, value}]}; exit code in *rc.
inline nlohmann::json web_ifc(const std::string& file, int* rc, std::string* out) {
  *rc = fixture::sh("node " + fixture::js_dir() + "/ifc_check.js " + file + " 2>/dev/null", out);
  if (*rc != 0 || out->find('{') == std::string::npos) return {};
  return nlohmann::json::parse(out->substr(out->find('{')));
}

#ifdef C3D_HAVE_IFCPP
struct IfcppRead {
  int problems = 0;
  std::string messages;
  size_t entities = 0;
  std::map<std::string, double> gross;  // tag -> GrossArea / GrossSideArea
  std::map<std::string, int> storeys;          // building name -> IfcBuildingStoreys aggregated
  std::map<std::string, std::string> storey;   // element tag -> name of the storey containing it
  std::map<std::string, bool> is_external;     // element tag -> Pset_*Common.IsExternal
};

inline void on_message(void* target, shared_ptr<StatusCallback::Message> m) {
  auto* r = static_cast<IfcppRead*>(target);
  if (m->m_message_type == StatusCallback::MESSAGE_TYPE_WARNING ||
      m->m_message_type == StatusCallback::MESSAGE_TYPE_ERROR) {
    ++r->problems;
    r->messages += std::string(m->m_message_text.begin(), m->m_message_text.end()) + "\n";
  }
}

inline std::string narrow(const std::wstring& w) { return std::string(w.begin(), w.end()); }

inline std::string ifcpp_name(const shared_ptr<IfcRoot>& o) {
  return o && o->m_Name ? narrow(o->m_Name->m_value) : "";
}

// Storeys per building (IfcRelAggregates) and the storey of every element
// (IfcRelContainedInSpatialStructure; a slab aggregated in a contained IfcRoof: the roof's).
inline void read_ifcpp_storeys(BuildingModel& model, IfcppRead& out) {
  std::map<IfcObjectDefinition*, IfcObjectDefinition*> parent;
  std::map<IfcObjectDefinition*, std::string> storey_of;
  for (const auto& [id, e] : model.getMapIfcEntities()) {
    if (auto agg = std::dynamic_pointer_cast<IfcRelAggregates>(e)) {
      for (const auto& o : agg->m_RelatedObjects) {
        parent[o.get()] = agg->m_RelatingObject.get();
        if (std::dynamic_pointer_cast<IfcBuildingStorey>(o) &&
            std::dynamic_pointer_cast<IfcBuilding>(agg->m_RelatingObject))
          ++out.storeys[ifcpp_name(agg->m_RelatingObject)];
      }
    } else if (auto c = std::dynamic_pointer_cast<IfcRelContainedInSpatialStructure>(e)) {
      for (const auto& p : c->m_RelatedElements) storey_of[p.get()] = ifcpp_name(c->m_RelatingStructure);
    }
  }
  for (const auto& [id, e] : model.getMapIfcEntities()) {
    auto el = std::dynamic_pointer_cast<IfcElement>(e);
    if (!el || !el->m_Tag || std::dynamic_pointer_cast<IfcRoof>(e)) continue;
    auto it = storey_of.find(el.get());
    if (it == storey_of.end() && parent.count(el.get())) it = storey_of.find(parent[el.get()]);
    if (it != storey_of.end()) out.storey[narrow(el->m_Tag->m_value)] = it->second;
  }
}

inline void read_ifcpp_is_external(const IfcRelDefinesByProperties& rel, IfcppRead& out) {
  auto pset = std::dynamic_pointer_cast<IfcPropertySet>(rel.m_RelatingPropertyDefinition);
  if (!pset || !pset->m_Name) return;
  const std::string name = narrow(pset->m_Name->m_value);
  if (name.rfind("Pset_", 0) != 0 || name.size() < 6 || name.substr(name.size() - 6) != "Common") return;
  for (const auto& p : pset->m_HasProperties) {
    auto v = std::dynamic_pointer_cast<IfcPropertySingleValue>(p);
    if (!v || !v->m_Name || narrow(v->m_Name->m_value) != "IsExternal") continue;
    auto b = std::dynamic_pointer_cast<IfcBoolean>(v->m_NominalValue);
    for (const auto& o : rel.m_RelatedObjects) {
      auto el = std::dynamic_pointer_cast<IfcElement>(o);
      if (b && el && el->m_Tag && !std::dynamic_pointer_cast<IfcRoof>(o))
        out.is_external[narrow(el->m_Tag->m_value)] = b->m_value;
    }
  }
}

inline IfcppRead read_with_ifcpp(std::string content) {
  IfcppRead out;
  auto model = std::make_shared<BuildingModel>();
  ReaderSTEP reader;
  reader.setMessageCallBack(&out, &on_message);
  model->setMessageCallBack(&out, &on_message);
  reader.loadModelFromString(content, model);
  out.entities = model->getMapIfcEntities().size();
  read_ifcpp_storeys(*model, out);
  for (const auto& [id, e] : model->getMapIfcEntities()) {
    auto rel = std::dynamic_pointer_cast<IfcRelDefinesByProperties>(e);
    if (!rel) continue;
    read_ifcpp_is_external(*rel, out);
    auto qto = std::dynamic_pointer_cast<IfcElementQuantity>(rel->m_RelatingPropertyDefinition);
    if (!qto) continue;
    for (const auto& obj : rel->m_RelatedObjects) {
      auto el = std::dynamic_pointer_cast<IfcElement>(obj);
      if (!el || !el->m_Tag) continue;
      for (const auto& q : qto->m_Quantities) {
        auto qa = std::dynamic_pointer_cast<IfcQuantityArea>(q);
        if (!qa || !qa->m_Name || !qa->m_AreaValue) continue;
        std::string name = narrow(qa->m_Name->m_value);
        if (name == "GrossArea" || name == "GrossSideArea")
          out.gross[narrow(el->m_Tag->m_value)] = qa->m_AreaValue->m_value;
      }
    }
  }
  return out;
}
#endif

}  // namespace c3d::check
