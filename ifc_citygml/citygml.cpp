// CityGML writer, 2.0 or 3.0: Building (BuildingPart per roof level) with thematic
// boundary surfaces in lod2MultiSurface and a lod2Solid whose shell points at those
// polygons by xlink:href. Each surface once (docs/exports.md): an element's
// surface holds its faces in the solid (a roof's part inside the walls) and its
// parts outside it (the overhang; an outer ceiling whole), the solid refers to
// the former; a solid face on no element is written inline. An LoD 1.2 / 1.3
// fallback has a lod1Solid instead: in 3.0 with its boundary surfaces in
// lod1MultiSurface; in 2.0, whose boundary surfaces exist from LoD 2 on, with
// its polygons inline and no boundary surfaces (its element areas are in the
// building's attributes). Of the lower LoDs of an LoD 2 model, the highest
// (1.3 before 1.2) is the lod1Solid, polygons inline: each CityGML LoD holds one
// solid, and neither version has boundary surfaces for it here. The two
// versions differ in namespaces and wrappers only: 2.0 bldg:boundedBy /
// gen:stringAttribute / measuredHeight, 3.0 core:boundary with con: surfaces /
// core:genericAttribute / con:height, on GML 3.2.
#include <cctype>
#include <string>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "core/geometry/geometry.h"
#include "ifc_citygml/attributes.h"
#include "ifc_citygml/detail.h"
#include "ifc_citygml/spool.h"
#include "ifc_citygml/surfaces.h"
#include "ifc_citygml/export.h"

namespace c3d {
namespace {

using exp::fixed;
using exp::xml_escape;

// gml:id must be an NCName.
std::string ncname(const std::string& s) {
  std::string out = "c3d_";
  for (char c : s) out += (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '.') ? c : '_';
  return out;
}

class GmlWriter : public ExportWriter {
 public:
  // The body goes to a spool beside the file: the envelope that heads the
  // file needs every building first.
  GmlWriter(const BatchModel& header, const std::string& path, int version)
      : path_(path), body_(path, ".body.part"), os_(body_.out()), frame_(header.frame),
        epsg_(header.epsg), v3_(version == 3) {}

  void add(const BatchModel& page) override {
    page_ = &page;
    for (const auto& r : page.results)
      for (const auto& b : r.buildings) {
        extend_envelope(b);
        building(r, b);
      }
    if (!os_) throw std::runtime_error(path_ + ": write failed");
  }

  std::vector<std::string> finish() override {
    std::ofstream file(path_, std::ios::binary);
    if (!file) throw std::runtime_error(path_ + ": cannot open for writing");
    header(file);
    body_.copy_to(file);
    file << "</core:CityModel>\n";
    if (!file.flush()) throw std::runtime_error(path_ + ": write failed");
    return {path_};
  }

 private:
  const std::string path_;
  exp::Spool body_;
  std::ostream& os_;
  const LocalFrame frame_;
  const int epsg_;
  const bool v3_;
  const BatchModel* page_ = nullptr;
  Vec3 lo_ = Vec3::Constant(1e300), hi_ = Vec3::Constant(-1e300);  // element faces, local

  std::string srs() const {
    return epsg_ > 0 ? " srsName=\"urn:ogc:def:crs:EPSG::" + std::to_string(epsg_) + "\"" : "";
  }

  void pos_list(const Ring3& ring) {
    os_ << "<gml:posList srsDimension=\"3\">";
    for (size_t i = 0; i <= ring.size(); ++i) {  // GML rings repeat the first point
      Vec3 w = frame_.to_world(ring[i % ring.size()]);
      os_ << (i ? " " : "") << fixed(w.x(), 3) << ' ' << fixed(w.y(), 3) << ' ' << fixed(w.z(), 3);
    }
    os_ << "</gml:posList>";
  }

  void polygon(const Face& f, const std::string& id) {
    os_ << "<gml:Polygon gml:id=\"" << id << "\"><gml:exterior><gml:LinearRing>";
    pos_list(f.ring);
    os_ << "</gml:LinearRing></gml:exterior>";
    for (size_t k = 0; k < f.holes.size(); ++k) {
      os_ << "<gml:interior><gml:LinearRing>";
      pos_list(exp::hole_oriented(f, k));
      os_ << "</gml:LinearRing></gml:interior>";
    }
    os_ << "</gml:Polygon>\n";
  }

  // kind: "string", "double" or "int".
  void attr(const std::string& kind, const char* name, const std::string& value) {
    if (v3_) {
      std::string type = std::string(1, char(std::toupper(kind[0]))) + kind.substr(1) + "Attribute";
      os_ << "<core:genericAttribute><gen:" << type << "><gen:name>" << name
          << "</gen:name><gen:value>" << value << "</gen:value></gen:" << type
          << "></core:genericAttribute>\n";
    } else {
      os_ << "<gen:" << kind << "Attribute name=\"" << name << "\"><gen:value>" << value
          << "</gen:value></gen:" << kind << "Attribute>\n";
    }
  }
  void str_attr(const char* name, const std::string& v) { attr("string", name, xml_escape(v)); }
  void dbl_attr(const char* name, double v, int decimals) { attr("double", name, fixed(v, decimals)); }
  void int_attr(const char* name, long v) { attr("int", name, std::to_string(v)); }

  void header(std::ostream& os) const {
    os << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
    if (v3_)
      os << "<core:CityModel xmlns:core=\"http://www.opengis.net/citygml/3.0\""
            " xmlns:bldg=\"http://www.opengis.net/citygml/building/3.0\""
            " xmlns:con=\"http://www.opengis.net/citygml/construction/3.0\""
            " xmlns:gen=\"http://www.opengis.net/citygml/generics/3.0\""
            " xmlns:gml=\"http://www.opengis.net/gml/3.2\""
            " xmlns:xlink=\"http://www.w3.org/1999/xlink\">\n";
    else
      os << "<core:CityModel xmlns:core=\"http://www.opengis.net/citygml/2.0\""
            " xmlns:bldg=\"http://www.opengis.net/citygml/building/2.0\""
            " xmlns:gen=\"http://www.opengis.net/citygml/generics/2.0\""
            " xmlns:gml=\"http://www.opengis.net/gml\""
            " xmlns:xlink=\"http://www.w3.org/1999/xlink\">\n";
    os << "<gml:name>Cadastre3D LoD2 buildings</gml:name>\n";
    envelope(os);
  }

  void extend_envelope(const Building& b) {
    for (const auto& e : b.elements)
      for (const auto& f : e.faces)
        for (const auto& p : f.ring) { lo_ = lo_.cwiseMin(p); hi_ = hi_.cwiseMax(p); }
  }

  void envelope(std::ostream& os) const {
    if (lo_.x() > hi_.x()) return;
    const Vec3 lo = frame_.to_world(lo_), hi = frame_.to_world(hi_);
    os << "<gml:boundedBy><gml:Envelope" << srs() << " srsDimension=\"3\"><gml:lowerCorner>"
        << fixed(lo.x(), 3) << ' ' << fixed(lo.y(), 3) << ' ' << fixed(lo.z(), 3)
        << "</gml:lowerCorner><gml:upperCorner>" << fixed(hi.x(), 3) << ' ' << fixed(hi.y(), 3)
        << ' ' << fixed(hi.z(), 3) << "</gml:upperCorner></gml:Envelope></gml:boundedBy>\n";
  }

  void parcel_reference(const ParcelResult& r) {
    if (v3_) {  // the target must be a URI: the parcel id, percent-encoded
      os_ << "<core:externalReference><core:ExternalReference><core:targetResource>"
             "urn:cadastre3d:la_spatialunit:"
          << exp::uri_escape(r.parcel_id)
          << "</core:targetResource><core:informationSystem>urn:cadastre3d:la_spatialunit"
             "</core:informationSystem></core:ExternalReference></core:externalReference>\n";
      return;
    }
    os_ << "<core:externalReference><core:informationSystem>urn:cadastre3d:la_spatialunit"
           "</core:informationSystem><core:externalObject><core:name>"
        << xml_escape(r.parcel_id) << "</core:name></core:externalObject></core:externalReference>\n";
  }

  // "lod1" for an LoD 1.2 prism, "lod2" for the element model.
  static const char* lod(const Building& b) { return b.lod == Lod::Lod22 ? "lod2" : "lod1"; }
  bool prism_in_v2(const Building& b) const { return !v3_ && std::string(lod(b)) == "lod1"; }

  void building_attributes(const ParcelResult& r, const Building& b) {
    const Parcel* p = exp::parcel_of(*page_, r);
    str_attr("parcelId", r.parcel_id);
    str_attr("rightType", p ? p->right_type : "");
    BuildingTotals t = totals(b);
    dbl_attr("roofArea", t.roof, 3);
    dbl_attr("roofAreaSigma", t.sigma_roof, 3);
    dbl_attr("wallArea", t.wall, 3);
    dbl_attr("wallAreaSigma", t.sigma_wall, 3);
    dbl_attr("partyWallArea", t.party_wall, 3);
    dbl_attr("partyWallAreaSigma", t.sigma_party_wall, 3);
    dbl_attr("groundArea", t.ground, 3);
    dbl_attr("groundAreaSigma", t.sigma_ground, 3);
    dbl_attr("outerCeilingArea", t.outer_ceiling, 3);
    dbl_attr("outerCeilingAreaSigma", t.sigma_outer_ceiling, 3);
    dbl_attr("volume", b.volume, 3);
    dbl_attr("eaveHeight", b.eave_height, 3);
    str_attr("solidValid", b.solid_valid ? "true" : "false");
    str_attr("lod", to_string(b.lod));
    str_attr("lodNote", b.lod_note);
    const exp::QualityAttributes q = exp::quality_attributes(b, frame_);
    for (const auto& [k, v] : q.texts) str_attr(exp::camel_case(k).c_str(), v);
    for (const auto& [k, v] : q.numbers) dbl_attr(exp::camel_case(k).c_str(), v, 3);
    for (const auto& [k, v] : q.counts) int_attr(exp::camel_case(k).c_str(), v);
    if (const LodShell* l = lod1_shell(b)) str_attr("lod1Solid", std::string("LoD ") + to_string(l->lod));
  }

  // This building's surfaces, each once (set by building()).
  exp::BuildingSurfaces surfaces_;

  std::string solid_polygon_id(const Building& b, size_t j) const {
    return ncname(b.id) + "_s" + std::to_string(j);
  }

  void boundary_surface(const Building& b, size_t e) {
    const Element& el = b.elements[e];
    const std::string id = ncname(b.id) + "_e" + std::to_string(e);
    const char* tag = exp::citygml_surface(el.type);
    const std::string open = v3_ ? "<core:boundary><con:" : "<bldg:boundedBy><bldg:";
    const std::string close = v3_ ? "</con:" + std::string(tag) + "></core:boundary>\n"
                                  : "</bldg:" + std::string(tag) + "></bldg:boundedBy>\n";
    const std::string surfaces = std::string(v3_ ? "core:" : "bldg:") + lod(b) + "MultiSurface";
    os_ << open << tag << " gml:id=\"" << id << "\">\n";
    str_attr("elementType", to_string(el.type));
    str_attr("isPartyWall", el.type == ElementType::PartyWall ? "true" : "false");
    dbl_attr("area", el.area, 4);
    dbl_attr("areaSigma", el.sigma_area, 4);
    dbl_attr("planArea", el.plan_area, 4);
    dbl_attr("slope", el.slope_deg, 2);
    dbl_attr("azimuth", el.azimuth_deg, 2);
    int_attr("supportPoints", el.support_points);
    dbl_attr("rmse", el.rmse, 4);
    str_attr("wallEvidence", to_string(el.evidence));
    os_ << "<" << surfaces << "><gml:MultiSurface>\n";
    for (const auto& p : surfaces_.solid) {
      if (p.element != int(e)) continue;
      os_ << "<gml:surfaceMember>";
      polygon(p.face, solid_polygon_id(b, size_t(p.solid_face)));
      os_ << "</gml:surfaceMember>\n";
    }
    size_t k = 0;
    for (const auto& p : surfaces_.outside) {
      if (p.element != int(e)) continue;
      os_ << "<gml:surfaceMember>";
      polygon(p.face, id + "_o" + std::to_string(k++));
      os_ << "</gml:surfaceMember>\n";
    }
    os_ << "</gml:MultiSurface></" << surfaces << ">\n" << close;
  }

  // A solid of these faces; with `refer_to`, the faces on an element by
  // reference to their polygons in its boundary surfaces.
  void solid_property(const std::string& property, const std::string& id, const std::vector<Face>& faces,
                      const Building* refer_to) {
    const char* shell = v3_ ? "gml:Shell" : "gml:CompositeSurface";  // GML 3.2 solids have shells
    os_ << "<" << property << "><gml:Solid gml:id=\"" << id << "\"><gml:exterior><" << shell << ">\n";
    for (size_t j = 0; j < faces.size(); ++j) {
      if (refer_to && surfaces_.solid[j].element >= 0) {
        os_ << "<gml:surfaceMember xlink:href=\"#" << solid_polygon_id(*refer_to, j) << "\"/>\n";
      } else {
        os_ << "<gml:surfaceMember>";
        polygon(faces[j], id + "_" + std::to_string(j));
        os_ << "</gml:surfaceMember>\n";
      }
    }
    os_ << "</" << shell << "></gml:exterior></gml:Solid></" << property << ">\n";
  }

  // The primary solid: its element faces by reference (inline for a 2.0
  // prism, which has no boundary surfaces).
  void solid(const Building& b) {
    if (b.solid.empty()) return;
    const std::string property = std::string(v3_ ? "core:" : "bldg:") + lod(b) + "Solid";
    solid_property(property, ncname(b.id) + "_solid", b.solid, prism_in_v2(b) ? nullptr : &b);
  }

  // The lower LoD written as the lod1Solid of an LoD 2 model: the highest.
  static const LodShell* lod1_shell(const Building& b) {
    if (std::string(lod(b)) != "lod2") return nullptr;
    const LodShell* best = nullptr;
    for (const auto& l : b.lower_lods)
      if (!l.faces.empty() && l.lod != Lod::Lod22 && (!best || l.lod > best->lod)) best = &l;
    return best;
  }

  void lower_solid(const Building& b) {
    if (const LodShell* l = lod1_shell(b))
      solid_property(v3_ ? "core:lod1Solid" : "bldg:lod1Solid", ncname(b.id) + "_lod1s", l->faces, nullptr);
  }

  void heights(const Building& b) {
    if (v3_) {
      os_ << "<con:height><con:Height><con:highReference>highestRoofEdge</con:highReference>"
             "<con:lowReference>lowestGroundPoint</con:lowReference><con:status>measured"
             "</con:status><con:value uom=\"m\">"
          << fixed(b.ridge_height, 3) << "</con:value></con:Height></con:height>\n"
          << "<bldg:storeysAboveGround>" << std::max(b.storeys, 0) << "</bldg:storeysAboveGround>\n";
      return;
    }
    os_ << "<bldg:measuredHeight uom=\"m\">" << fixed(b.ridge_height, 3)
        << "</bldg:measuredHeight>\n<bldg:storeysAboveGround>" << std::max(b.storeys, 0)
        << "</bldg:storeysAboveGround>\n";
  }

  void building(const ParcelResult& r, const Building& b) {
    int levels = 1;
    std::vector<int> lv = exp::element_levels(b, &levels);
    os_ << "<core:cityObjectMember><bldg:Building gml:id=\"" << ncname(b.id) << "\">\n"
        << "<gml:name>" << xml_escape(b.id) << "</gml:name>\n";
    parcel_reference(r);
    building_attributes(r, b);
    // 2.0: heights, solid, then surfaces; 3.0: surfaces, solid, then heights.
    surfaces_ = exp::building_surfaces(b);
    if (!v3_) heights(b), lower_solid(b), solid(b);
    if (levels == 1 && !prism_in_v2(b))
      for (size_t e = 0; e < b.elements.size(); ++e) boundary_surface(b, e);
    if (v3_) lower_solid(b), solid(b), heights(b);
    const char* part = v3_ ? "bldg:buildingPart" : "bldg:consistsOfBuildingPart";
    for (int l = 0; levels > 1 && l < levels; ++l) {
      os_ << "<" << part << "><bldg:BuildingPart gml:id=\"" << ncname(b.id) << "_part" << l
          << "\">\n<gml:name>" << xml_escape(b.id) << " level " << l << "</gml:name>\n";
      str_attr("roofLevel", std::to_string(l));
      for (size_t e = 0; e < b.elements.size(); ++e)
        if (lv[e] == l) boundary_surface(b, e);
      os_ << "</bldg:BuildingPart></" << part << ">\n";
    }
    os_ << "</bldg:Building></core:cityObjectMember>\n";
  }
};

}  // namespace

std::unique_ptr<ExportWriter> citygml_writer(const BatchModel& header, const std::string& path, int version) {
  if (version != 2 && version != 3) throw std::invalid_argument("CityGML version must be 2 or 3");
  return std::make_unique<GmlWriter>(header, path, version);
}

void write_citygml(const BatchModel& model, const std::string& path, int version) {
  auto w = citygml_writer(model, path, version);
  w->add(model);
  w->finish();
}

}  // namespace c3d
