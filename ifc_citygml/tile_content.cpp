#include "ifc_citygml/tile_content.h"

#include <cmath>
#include <cstdint>
#include <functional>

#include <nlohmann/json.hpp>

#include "core/mesh/glb.h"

namespace c3d::tiles {

using nlohmann::json;

std::array<float, 3> element_colour(ElementType t) {
  switch (t) {
    case ElementType::Roof: return {0.71f, 0.33f, 0.24f};          // terracotta
    case ElementType::Wall: return {0.91f, 0.89f, 0.82f};          // plaster
    case ElementType::PartyWall: return {0.79f, 0.66f, 0.30f};     // ochre
    case ElementType::Ground: return {0.50f, 0.50f, 0.50f};        // grey
    case ElementType::OuterCeiling: return {0.42f, 0.56f, 0.75f};  // blue
  }
  return {1, 1, 1};
}

namespace {

using namespace gltf;

// The binary chunk and its buffer views. Views start on 8 bytes, as
// EXT_structural_metadata asks of property values.
class Binary {
 public:
  json views = json::array();
  std::vector<unsigned char> bytes;

  template <typename T>
  int view(const std::vector<T>& values, bool vertex_attribute = false) {
    while (bytes.size() % 8) bytes.push_back(0);
    json v{{"buffer", 0}, {"byteOffset", bytes.size()}, {"byteLength", values.size() * sizeof(T)}};
    if (vertex_attribute) v["target"] = kArrayBuffer;
    const auto* p = reinterpret_cast<const unsigned char*>(values.data());
    bytes.insert(bytes.end(), p, p + values.size() * sizeof(T));
    views.push_back(v);
    return int(views.size()) - 1;
  }
};

// The triangles as vertex arrays, vertex by vertex.
struct Vertices {
  std::vector<float> position, normal, colour, building, element;
  std::array<float, 3> lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};

  void face(const std::vector<Vec3>& tris, const Vec3& centre, ElementType type, float b, float e) {
    Vec3 n = Vec3::Zero();
    for (size_t i = 0; i + 2 < tris.size(); i += 3) n += (tris[i + 1] - tris[i]).cross(tris[i + 2] - tris[i]);
    if (!(n.norm() > 0)) return;  // no area: nothing to draw
    n.normalize();
    const std::array<float, 3> c = element_colour(type);
    for (const Vec3& w : tris) {
      const Vec3 v = w - centre;
      for (int k = 0; k < 3; ++k) {
        const float f = float(v[k]);
        position.push_back(f), normal.push_back(float(n[k])), colour.push_back(c[size_t(k)]);
        lo[size_t(k)] = std::min(lo[size_t(k)], f), hi[size_t(k)] = std::max(hi[size_t(k)], f);
      }
      building.push_back(b), element.push_back(e);
    }
  }
};

// A property table's columns: each property's values as EXT_structural_metadata stores them.
class Table {
 public:
  Table(Binary& bin, size_t count) : bin_(bin), count_(count) {}
  void text(const std::string& name, const std::function<std::string(size_t)>& at) {
    std::vector<unsigned char> chars;
    std::vector<uint32_t> offsets{0};
    for (size_t i = 0; i < count_; ++i) {
      const std::string s = at(i);
      chars.insert(chars.end(), s.begin(), s.end());
      offsets.push_back(uint32_t(chars.size()));
    }
    if (chars.empty()) chars.push_back(0);  // every string empty: a buffer view holds at least a byte
    const int values = bin_.view(chars);
    properties_[name] = {{"values", values}, {"stringOffsets", bin_.view(offsets)}, {"stringOffsetType", "UINT32"}};
    classes_[name] = {{"type", "STRING"}};
  }
  template <typename T>
  void number(const std::string& name, const char* component, const std::function<T(size_t)>& at,
              bool unvalued_is_minus_one = false) {
    std::vector<T> v(count_);
    for (size_t i = 0; i < count_; ++i) v[i] = at(i);
    properties_[name] = {{"values", bin_.view(v)}};
    classes_[name] = {{"type", "SCALAR"}, {"componentType", component}};
    // -1 is "not valued"; as the default too, so a reader that swaps noData
    // for the default (3d-tiles-renderer: 0 without one) still reads -1.
    if (unvalued_is_minus_one) classes_[name]["noData"] = -1, classes_[name]["default"] = -1;
  }
  json table(const std::string& cls) const { return {{"class", cls}, {"count", count_}, {"properties", properties_}}; }
  json schema_class() const { return {{"properties", classes_}}; }

 private:
  Binary& bin_;
  size_t count_;
  json properties_ = json::object(), classes_ = json::object();
};

constexpr const char* kAreaNames[6] = {"roof_area_m2", "wall_area_m2", "party_wall_area_m2",
                                       "ground_area_m2", "outer_ceiling_area_m2", "volume_m3"};

Table building_table(Binary& bin, const std::vector<TileBuilding>& bs) {
  Table t(bin, bs.size());
  t.text("building_id", [&](size_t i) { return bs[i].building_id; });
  t.text("parcel_id", [&](size_t i) { return bs[i].parcel_id; });
  t.text("status", [&](size_t i) { return bs[i].status; });
  t.text("lod", [&](size_t i) { return bs[i].lod; });
  for (size_t k = 0; k < 6; ++k) t.number<double>(kAreaNames[k], "FLOAT64", [&](size_t i) { return bs[i].areas[k]; });
  t.number<double>("building_value", "FLOAT64", [&](size_t i) { return bs[i].building_value; }, true);
  t.number<double>("njop", "FLOAT64", [&](size_t i) { return bs[i].njop; }, true);
  t.number<double>("njop_per_m2", "FLOAT64", [&](size_t i) { return bs[i].njop_per_m2; }, true);
  t.number<double>("tax", "FLOAT64", [&](size_t i) { return bs[i].tax; }, true);
  t.text("currency", [&](size_t i) { return bs[i].currency; });
  return t;
}

Table element_table(Binary& bin, const std::vector<std::pair<uint32_t, const TileElement*>>& es) {
  Table t(bin, es.size());
  t.number<uint32_t>("building", "UINT32", [&](size_t i) { return es[i].first; });
  t.text("type", [&](size_t i) { return std::string(to_string(es[i].second->type)); });
  t.number<double>("area_m2", "FLOAT64", [&](size_t i) { return es[i].second->area; });
  t.number<double>("sigma_area_m2", "FLOAT64", [&](size_t i) { return es[i].second->sigma_area; });
  t.number<double>("plan_area_m2", "FLOAT64", [&](size_t i) { return es[i].second->plan_area; });
  t.number<double>("slope_deg", "FLOAT64", [&](size_t i) { return es[i].second->slope_deg; });
  t.number<int32_t>("support_points", "INT32", [&](size_t i) { return int32_t(es[i].second->support_points); });
  t.number<double>("rmse_m", "FLOAT64", [&](size_t i) { return es[i].second->rmse; });
  t.number<double>("amount", "FLOAT64", [&](size_t i) { return es[i].second->amount; }, true);
  return t;
}

json accessor(int view, size_t count, const char* type) {
  return {{"bufferView", view}, {"componentType", kFloat}, {"count", count}, {"type", type}};
}

json gltf_json(Binary& bin, const Vertices& v, const std::vector<TileBuilding>& bs,
               const std::vector<std::pair<uint32_t, const TileElement*>>& es) {
  const size_t n = v.building.size();
  json accessors = json::array({accessor(bin.view(v.position, true), n, "VEC3"),
                                accessor(bin.view(v.normal, true), n, "VEC3"),
                                accessor(bin.view(v.colour, true), n, "VEC3"),
                                accessor(bin.view(v.building, true), n, "SCALAR"),
                                accessor(bin.view(v.element, true), n, "SCALAR")});
  accessors[0]["min"] = v.lo, accessors[0]["max"] = v.hi;
  const Table buildings = building_table(bin, bs), elements = element_table(bin, es);
  json ids = json::array({{{"featureCount", bs.size()}, {"attribute", 0}, {"propertyTable", 0}, {"label", "building"}},
                          {{"featureCount", es.size()}, {"attribute", 1}, {"propertyTable", 1}, {"label", "element"}}});
  json primitive{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}, {"COLOR_0", 2}, {"_FEATURE_ID_0", 3}, {"_FEATURE_ID_1", 4}}},
                 {"mode", kTriangles},
                 {"material", 0},
                 {"extensions", {{"EXT_mesh_features", {{"featureIds", ids}}}}}};
  const double half = std::sqrt(0.5);
  json schema{{"id", "cadastre3d"},
              {"classes", {{"building", buildings.schema_class()}, {"element", elements.schema_class()}}}};
  return {{"asset", {{"version", "2.0"}, {"generator", "cadastre3d"}}},
          {"extensionsUsed", {"EXT_mesh_features", "EXT_structural_metadata"}},
          {"extensions",
           {{"EXT_structural_metadata",
             {{"schema", schema}, {"propertyTables", {buildings.table("building"), elements.table("element")}}}}}},
          {"scene", 0},
          {"scenes", {{{"nodes", {0}}}}},
          {"nodes", {{{"mesh", 0}, {"rotation", {-half, 0.0, 0.0, half}}}}},  // +Z up onto glTF's +Y
          {"materials",
           {{{"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 1}}},
             {"doubleSided", true}}}},
          {"meshes", {{{"primitives", {primitive}}}}},
          {"buffers", {{{"byteLength", bin.bytes.size()}}}},
          {"bufferViews", bin.views},
          {"accessors", accessors}};
}

}  // namespace

std::vector<unsigned char> tile_glb(const std::vector<TileBuilding>& buildings, const Vec3& centre) {
  Vertices v;
  std::vector<std::pair<uint32_t, const TileElement*>> elements;
  for (size_t b = 0; b < buildings.size(); ++b)
    for (const TileElement& e : buildings[b].elements) {
      for (const auto& face : e.faces) v.face(face, centre, e.type, float(b), float(elements.size()));
      elements.emplace_back(uint32_t(b), &e);
    }
  Binary bin;
  const std::string text = gltf_json(bin, v, buildings, elements).dump();
  return glb_container(text, std::move(bin.bytes));
}

}  // namespace c3d::tiles
