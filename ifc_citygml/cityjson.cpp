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
#include <algorithm>
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
#include "ifc_citygml/spool.h"
#include "ifc_citygml/surfaces.h"

namespace c3d {
namespace {

using nlohmann::json;
constexpr double kScale = kExportGridM;  // m per integer unit of the vertices

std::array<long long, 3> grid(const Vec3& local) {
  return {std::llround(local.x() / kScale), std::llround(local.y() / kScale),
          std::llround(local.z() / kScale)};
}

// A grid point's integer coordinates, hashed for the de-duplicating map.
struct GridHash {
  size_t operator()(const std::array<long long, 3>& k) const {
    return std::hash<long long>()(k[0] * 73856093LL ^ k[1] * 19349663LL ^ k[2] * 83492791LL);
  }
};

// Distinct vertices a generation of the de-duplicating map holds (~16 MB of
// map): hundreds of buildings, far more than lie between two neighbours that
// share a corner in the layer's order, while the map stays bounded.
constexpr size_t kVertexGeneration = size_t(1) << 18;

// The vertex list, de-duplicated on the grid. A streamed file writes each new
// vertex to its spool as it comes; a feature of CityJSONSeq keeps its few
// vertices in memory. The map keeps two generations: once the current one
// holds kVertexGeneration vertices it becomes the old one at the next
// building (a vertex met again moves back to the current one), so memory is
// bounded and a vertex shared by buildings further apart in the layer's order
// than two generations is listed twice (docs/exports.md, "CityJSON").
class Vertices {
 public:
  explicit Vertices(exp::Spool* spool = nullptr) : spool_(spool) {}
  int index(const Vec3& local) {
    const auto k = grid(local);
    if (auto it = current_.find(k); it != current_.end()) return it->second;
    if (auto it = old_.find(k); it != old_.end()) return current_[k] = it->second;
    json v = json::array({k[0], k[1], k[2]});
    if (spool_) spool_->out() << (count_ ? "," : "") << v.dump();
    else list_.push_back(std::move(v));
    current_[k] = count_;
    return count_++;
  }
  // Between buildings: start a new generation when the current one is full.
  void building_done() {
    if (current_.size() < kVertexGeneration) return;
    old_ = std::move(current_);
    current_ = {};
  }
  json take() { return std::move(list_); }

 private:
  using Map = std::unordered_map<std::array<long long, 3>, int, GridHash>;
  exp::Spool* spool_;
  Map current_, old_;
  int count_ = 0;
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
    geometry.push_back({{"type", "Solid"}, {"lod", to_string(b.lod)}, {"boundaries", json::array({shell})},
                        {"semantics", {{"surfaces", sem.surfaces}, {"values", json::array({values})}}}});
  }
  if (s.outside.empty()) return;
  Semantics sem(b, levels, level_count, described);
  json bounds = json::array(), values = json::array();
  for (const auto& p : s.outside) bounds.push_back(surface_json(v, p.face)), values.push_back(sem.of(p));
  geometry.push_back({{"type", "MultiSurface"}, {"lod", to_string(b.lod)}, {"boundaries", bounds},
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
  return {{"type", "Solid"}, {"lod", to_string(l.lod)}, {"boundaries", json::array({shell})},
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
            {"lod", to_string(b.lod)}, {"lod_note", b.lod_note}};
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

// Bounding box of every face written, on the vertex grid (local), grown a
// building at a time.
struct Extent {
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  void add(const Face& f) {
    for (const auto& p : f.ring) {
      const auto k = grid(p);
      const Vec3 q(k[0] * kScale, k[1] * kScale, k[2] * kScale);
      lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
    }
  }
  void add(const Building& b) {
    for (const auto& f : b.solid) add(f);
    for (const auto& e : b.elements) for (const auto& f : e.faces) add(f);
    for (const auto& l : b.lower_lods) for (const auto& f : l.faces) add(f);
  }
  // World coordinates.
  json to_json(const LocalFrame& frame) const {
    if (lo.x() > hi.x()) return json::array({0, 0, 0, 0, 0, 0});
    const Vec3 l = lo + frame.origin, h = hi + frame.origin;
    return json::array({l.x(), l.y(), l.z(), h.x(), h.y(), h.z()});
  }
};

// The CityJSON object without city objects and vertices (the CityJSONSeq header).
json header(const BatchModel& m, const Extent& extent) {
  const Vec3& t = m.frame.origin;
  json meta = {{"title", "Cadastre3D buildings"}, {"geographicalExtent", extent.to_json(m.frame)}};
  if (m.epsg > 0) meta["referenceSystem"] = "https://www.opengis.net/def/crs/EPSG/0/" + std::to_string(m.epsg);
  return {{"type", "CityJSON"}, {"version", "2.0"},
          {"transform", {{"scale", {kScale, kScale, kScale}}, {"translate", {t.x(), t.y(), t.z()}}}},
          {"metadata", meta}, {"CityObjects", json::object()}, {"vertices", json::array()}};
}

// The frame and CRS of a model, without its parcels.
BatchModel header_of(const BatchModel& m) {
  BatchModel h;
  h.frame = m.frame, h.epsg = m.epsg, h.crs_wkt = m.crs_wkt;
  return h;
}

std::ofstream open_for_writing(const std::string& path) {
  std::ofstream os(path, std::ios::binary);
  if (!os) throw std::runtime_error(path + ": cannot open for writing");
  return os;
}


// One CityJSON file: the city objects go to a spool as they come, with a
// small index (id, place) that puts them in the order of the id at the end
// (the order of a JSON object's keys here); the vertices go to a second spool.
class CityJsonWriter : public ExportWriter {
 public:
  CityJsonWriter(const BatchModel& header, const std::string& path)
      : header_(header_of(header)), path_(path), objects_(path, ".objects.part"),
        vertex_list_(path, ".vertices.part"), vertices_(&vertex_list_) {}

  void add(const BatchModel& page) override {
    for (const auto& r : page.results)
      for (const auto& b : r.buildings) {
        extent_.add(b);
        const std::uint64_t at = objects_.size();
        objects_.out() << json(b.id).dump() << ':' << building_object(vertices_, page, r, b).dump();
        vertices_.building_done();
        if (!objects_.out()) throw std::runtime_error(path_ + ": write failed");
        placed_.push_back({b.id, at, objects_.size() - at});
      }
  }

  std::vector<std::string> finish() override {
    // The document with empty objects and vertices, split where they go.
    const std::string doc = header(header_, extent_).dump();
    const std::string objects_at = "{\"CityObjects\":{", vertices_at = "\"vertices\":[]}";
    if (doc.rfind(objects_at, 0) != 0 || doc.size() < objects_at.size() + vertices_at.size() ||
        doc.compare(doc.size() - vertices_at.size(), vertices_at.size(), vertices_at) != 0)
      throw std::logic_error("CityJSON header out of the expected key order");
    std::ofstream os = open_for_writing(path_);
    os << objects_at;
    write_objects(os);
    os << doc.substr(objects_at.size(), doc.size() - objects_at.size() - 2);  // up to the vertices' '['
    vertex_list_.copy_to(os);
    os << "]}";
    if (!os.flush()) throw std::runtime_error(path_ + ": write failed");
    return {path_};
  }

 private:
  struct Placed {
    std::string id;
    std::uint64_t at, bytes;
  };
  // In the order of their ids; of two objects with one id the later one (as
  // assigning to a JSON object's key keeps).
  void write_objects(std::ostream& os) {
    std::stable_sort(placed_.begin(), placed_.end(), [](const Placed& a, const Placed& b) { return a.id < b.id; });
    bool first = true;
    for (size_t k = 0; k < placed_.size(); ++k) {
      if (k + 1 < placed_.size() && placed_[k + 1].id == placed_[k].id) continue;
      if (!first) os << ',';
      first = false;
      objects_.copy_to(os, placed_[k].at, placed_[k].bytes);
    }
  }
  const BatchModel header_;
  const std::string path_;
  exp::Spool objects_, vertex_list_;
  Vertices vertices_;
  Extent extent_;
  std::vector<Placed> placed_;
};

// CityJSONSeq: the features go to a spool, since the header line before them
// holds the extent of them all.
class CityJsonSeqWriter : public ExportWriter {
 public:
  CityJsonSeqWriter(const BatchModel& header, const std::string& path)
      : header_(header_of(header)), path_(path), features_(path, ".features.part") {}

  void add(const BatchModel& page) override {
    for (const auto& r : page.results)
      for (const auto& b : r.buildings) {
        extent_.add(b);
        Vertices v;  // each feature has its own vertices
        json feature = {{"type", "CityJSONFeature"}, {"id", b.id}};
        feature["CityObjects"][b.id] = building_object(v, page, r, b);
        feature["vertices"] = v.take();
        features_.out() << feature.dump() << '\n';
        if (!features_.out()) throw std::runtime_error(path_ + ": write failed");
      }
  }

  std::vector<std::string> finish() override {
    std::ofstream os = open_for_writing(path_);
    os << header(header_, extent_).dump() << '\n';
    features_.copy_to(os);
    if (!os.flush()) throw std::runtime_error(path_ + ": write failed");
    return {path_};
  }

 private:
  const BatchModel header_;
  const std::string path_;
  exp::Spool features_;
  Extent extent_;
};

}  // namespace

std::unique_ptr<ExportWriter> cityjson_writer(const BatchModel& header, const std::string& path) {
  return std::make_unique<CityJsonWriter>(header, path);
}

std::unique_ptr<ExportWriter> cityjson_seq_writer(const BatchModel& header, const std::string& path) {
  return std::make_unique<CityJsonSeqWriter>(header, path);
}

void write_cityjson(const BatchModel& model, const std::string& path) {
  auto w = cityjson_writer(model, path);
  w->add(model);
  w->finish();
}

void write_cityjson_seq(const BatchModel& model, const std::string& path) {
  auto w = cityjson_seq_writer(model, path);
  w->add(model);
  w->finish();
}

}  // namespace c3d
