// IFC4 (ADD2 TC1) STEP writer, own text output: IfcProject -> IfcSite (per parcel)
// -> IfcBuilding -> IfcBuildingStorey; roof slabs aggregated in an IfcRoof; walls,
// base slab, outer-ceiling covering contained in the storey. Geometry is one
// IfcTriangulatedFaceSet per element in coordinates local to the frame origin,
// georeferenced by IfcMapConversion. GlobalIds are hashes of stable keys.
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include "core/geometry/geometry.h"
#include "ifc_citygml/detail.h"
#include "ifc_citygml/export.h"

namespace c3d {
namespace {

uint64_t fnv1a(const std::string& s, uint64_t h) {
  for (unsigned char c : s) { h ^= c; h *= 1099511628211ull; }
  h ^= h >> 33; h *= 0xff51afd7ed558ccdull; h ^= h >> 33;  // murmur finaliser
  return h;
}

// 128-bit hash of the key in IFC's base-64 alphabet: 2 bits, then 21 x 6 bits.
std::string ifc_guid(const std::string& key) {
  static const char* kChars = "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz_$";
  const uint64_t hi = fnv1a(key, 1469598103934665603ull);
  const uint64_t lo = fnv1a(key, 0x9e3779b97f4a7c15ull);
  std::string g(22, '0');
  g[0] = kChars[hi >> 62];
  for (int i = 1; i < 22; ++i) {
    int shift = 126 - 6 * i;  // lowest bit of this 6-bit group
    uint64_t v = shift >= 64 ? hi >> (shift - 64)
                             : (lo >> shift) | (shift > 58 ? hi << (64 - shift) : 0);
    g[i] = kChars[v & 63];
  }
  return g;
}

// STEP string literal: quotes doubled, backslashes doubled, non-ASCII as \X2\hhhh\X0\.
std::string step_str(const std::string& s) {
  std::string out = "'";
  for (size_t i = 0; i < s.size();) {
    unsigned char c = s[i];
    if (c < 0x80) {
      if (c == '\'') out += "''";
      else if (c == '\\') out += "\\\\";
      else if (c >= 0x20) out += char(c);
      ++i;
      continue;
    }
    int len = c >= 0xF0 ? 4 : c >= 0xE0 ? 3 : 2;
    uint32_t cp = c & (0xFF >> (len + 1));
    for (int k = 1; k < len && i + k < s.size(); ++k) cp = (cp << 6) | (s[i + k] & 0x3F);
    i += len;
    char buf[16];
    if (cp <= 0xFFFF) std::snprintf(buf, sizeof buf, "\\X2\\%04X\\X0\\", cp);
    else std::snprintf(buf, sizeof buf, "\\X4\\%08X\\X0\\", cp);
    out += buf;
  }
  return out + "'";
}

// STEP real: always with a decimal point, trailing zeros dropped.
std::string step_real(double v, int decimals = 4) {
  std::string s = exp::fixed(v, decimals);
  if (s.find('.') != std::string::npos) {
    while (s.back() == '0') s.pop_back();
  } else {
    s += '.';
  }
  return s;
}

std::string refs(const std::vector<int>& ids) {
  std::string s = "(";
  for (size_t i = 0; i < ids.size(); ++i) s += (i ? ",#" : "#") + std::to_string(ids[i]);
  return s + ")";
}
std::string ref(int id) { return "#" + std::to_string(id); }

const char* qto_name(ElementType t) {
  switch (t) {
    case ElementType::Roof:
    case ElementType::Ground: return "Qto_SlabBaseQuantities";
    case ElementType::Wall:
    case ElementType::PartyWall: return "Qto_WallBaseQuantities";
    case ElementType::OuterCeiling: return "Qto_CoveringBaseQuantities";
  }
  return "";
}

class IfcWriter {
 public:
  IfcWriter(std::ostream& os, const BatchModel& m, const std::string& file_name)
      : os_(os), m_(m), file_name_(file_name) {}

  void run() {
    header();
    project();
    std::vector<int> sites;
    for (const auto& r : m_.results) sites.push_back(site(r));
    if (!sites.empty()) aggregate("project", project_, sites);
    os_ << "ENDSEC;\nEND-ISO-10303-21;\n";
  }

 private:
  std::ostream& os_;
  const BatchModel& m_;
  std::string file_name_;
  int next_ = 1;
  int project_ = 0, body_ = 0, footprint_ = 0, axis_ = 0;

  int add(const std::string& entity) {
    os_ << '#' << next_ << '=' << entity << ";\n";
    return next_++;
  }

  void header() {
    const char* sde = std::getenv("SOURCE_DATE_EPOCH");  // reproducible builds convention
    std::time_t t = sde ? std::time_t(std::atoll(sde)) : std::time(nullptr);
    char stamp[32];
    std::strftime(stamp, sizeof stamp, "%Y-%m-%dT%H:%M:%S", std::gmtime(&t));
    os_ << "ISO-10303-21;\nHEADER;\n"
           "FILE_DESCRIPTION(('ViewDefinition [ReferenceView_V1.2]'),'2;1');\n"
        << "FILE_NAME(" << step_str(file_name_) << ",'" << stamp
        << "',('Cadastre3D'),('Cadastre3D'),'cadastre3d " C3D_VERSION "','cadastre3d " C3D_VERSION
           "','');\n"
           "FILE_SCHEMA(('IFC4'));\nENDSEC;\nDATA;\n";
  }

  void project() {
    int origin = add("IFCCARTESIANPOINT((0.,0.,0.))");
    int z = add("IFCDIRECTION((0.,0.,1.))");
    int x = add("IFCDIRECTION((1.,0.,0.))");
    axis_ = add("IFCAXIS2PLACEMENT3D(" + ref(origin) + "," + ref(z) + "," + ref(x) + ")");
    int north = add("IFCDIRECTION((0.,1.))");
    int ctx = add("IFCGEOMETRICREPRESENTATIONCONTEXT($,'Model',3,1.E-05," + ref(axis_) + "," +
                  ref(north) + ")");
    body_ = add("IFCGEOMETRICREPRESENTATIONSUBCONTEXT('Body','Model',*,*,*,*," + ref(ctx) +
                ",$,.MODEL_VIEW.,$)");
    footprint_ = add("IFCGEOMETRICREPRESENTATIONSUBCONTEXT('FootPrint','Model',*,*,*,*," +
                     ref(ctx) + ",$,.PLAN_VIEW.,$)");
    std::vector<int> units = {add("IFCSIUNIT(*,.LENGTHUNIT.,$,.METRE.)"),
                              add("IFCSIUNIT(*,.AREAUNIT.,$,.SQUARE_METRE.)"),
                              add("IFCSIUNIT(*,.VOLUMEUNIT.,$,.CUBIC_METRE.)"),
                              add("IFCSIUNIT(*,.PLANEANGLEUNIT.,$,.RADIAN.)")};
    int ua = add("IFCUNITASSIGNMENT(" + refs(units) + ")");
    project_ = add("IFCPROJECT('" + ifc_guid("project") +
                   "',$,'Cadastre3D batch',$,$,$,$,(" + ref(ctx) + ")," + ref(ua) + ")");
    if (m_.epsg > 0) {
      int crs = add("IFCPROJECTEDCRS('EPSG:" + std::to_string(m_.epsg) + "',$,$,$,$,$,$)");
      const Vec3& o = m_.frame.origin;
      add("IFCMAPCONVERSION(" + ref(ctx) + "," + ref(crs) + "," + step_real(o.x(), 4) + "," +
          step_real(o.y(), 4) + "," + step_real(o.z(), 4) + ",1.,0.,1.)");
    }
  }

  int placement(int relative_to) {
    return add("IFCLOCALPLACEMENT(" + (relative_to ? ref(relative_to) : std::string("$")) + "," +
               ref(axis_) + ")");
  }

  void aggregate(const std::string& key, int whole, const std::vector<int>& parts) {
    add("IFCRELAGGREGATES('" + ifc_guid(key + "/aggregates") + "',$,$,$," + ref(whole) + "," +
        refs(parts) + ")");
  }

  void define(const std::string& key, int object, int definition) {
    add("IFCRELDEFINESBYPROPERTIES('" + ifc_guid(key) + "',$,$,$,(" + ref(object) + ")," +
        ref(definition) + ")");
  }

  int area_q(const char* name, double v) {
    return add(std::string("IFCQUANTITYAREA('") + name + "',$,$," + step_real(v, 4) + ",$)");
  }

  // Parcel outline (local x, y) as closed 2D polylines.
  int footprint(const Parcel* p) {
    if (!p || p->shape.empty()) return 0;
    std::vector<int> curves;
    auto ring = [&](const Ring2& r) {
      std::vector<int> pts;
      for (size_t i = 0; i <= r.size(); ++i) {
        Vec2 l = m_.frame.to_local(r[i % r.size()]);
        pts.push_back(add("IFCCARTESIANPOINT((" + step_real(l.x()) + "," + step_real(l.y()) + "))"));
      }
      curves.push_back(add("IFCPOLYLINE(" + refs(pts) + ")"));
    };
    for (const auto& poly : p->shape) {
      if (poly.outer.size() >= 3) ring(poly.outer);
      for (const auto& h : poly.holes) if (h.size() >= 3) ring(h);
    }
    if (curves.empty()) return 0;
    int rep = add("IFCSHAPEREPRESENTATION(" + ref(footprint_) + ",'FootPrint','Curve2D'," +
                  refs(curves) + ")");
    return add("IFCPRODUCTDEFINITIONSHAPE($,$,(" + ref(rep) + "))");
  }

  int site(const ParcelResult& r) {
    const Parcel* p = exp::parcel_of(m_, r);
    const std::string key = "site/" + r.parcel_id;
    int plc = placement(0);
    int shape = footprint(p);
    int site = add("IFCSITE('" + ifc_guid(key) + "',$," + step_str(r.parcel_id) + ",$,$," +
                   ref(plc) + "," + (shape ? ref(shape) : "$") + ",$,.ELEMENT.,$,$,$," +
                   step_str(r.parcel_id) + ",$)");
    std::vector<int> props = {
        add("IFCPROPERTYSINGLEVALUE('ParcelId',$,IFCIDENTIFIER(" + step_str(r.parcel_id) + "),$)"),
        add("IFCPROPERTYSINGLEVALUE('RightType',$,IFCLABEL(" + step_str(p ? p->right_type : "") +
            "),$)")};
    if (p && std::isfinite(p->official_area))
      props.push_back(add("IFCPROPERTYSINGLEVALUE('OfficialArea',$,IFCAREAMEASURE(" +
                          step_real(p->official_area) + "),$)"));
    int pset = add("IFCPROPERTYSET('" + ifc_guid(key + "/pset") +
                   "',$,'Cadastre3D_Parcel',$," + refs(props) + ")");
    define(key + "/pset/rel", site, pset);
    std::vector<int> buildings;
    for (const auto& b : r.buildings) buildings.push_back(building(b, plc));
    if (!buildings.empty()) aggregate(key, site, buildings);
    return site;
  }

  int building(const Building& b, int site_plc) {
    const std::string key = "building/" + b.id;
    int plc = placement(site_plc);
    int bldg = add("IFCBUILDING('" + ifc_guid(key) + "',$," + step_str(b.id) + ",$,$," + ref(plc) +
                   ",$,$,.ELEMENT.,$,$,$)");
    int vol = add("IFCQUANTITYVOLUME('GrossVolume',$,$," + step_real(b.volume) + ",$)");
    int qto = add("IFCELEMENTQUANTITY('" + ifc_guid(key + "/qto") +
                  "',$,'Qto_BuildingBaseQuantities',$,$,(" + ref(vol) + "))");
    define(key + "/qto/rel", bldg, qto);
    int splc = placement(plc);
    int storey = add("IFCBUILDINGSTOREY('" + ifc_guid(key + "/storey") + "',$,'Ground floor',$,$," +
                     ref(splc) + ",$,$,.ELEMENT.," + step_real(b.terrain_z) + ")");
    aggregate(key, bldg, {storey});
    contents(b, key, splc, storey);
    return bldg;
  }

  void contents(const Building& b, const std::string& key, int splc, int storey) {
    std::vector<int> contained, slabs;
    double roof_area = 0, roof_plan = 0;
    bool flat = true;
    for (size_t e = 0; e < b.elements.size(); ++e) {
      const Element& el = b.elements[e];
      int id = element(b, e, splc);
      if (!id) continue;
      if (el.type == ElementType::Roof) {
        slabs.push_back(id);
        roof_area += el.area;
        roof_plan += el.plan_area;
        flat = flat && el.slope_deg < 5;
      } else {
        contained.push_back(id);
      }
    }
    if (!slabs.empty()) {
      int roof = add("IFCROOF('" + ifc_guid(key + "/roof") + "',$,'Roof',$,$," + ref(placement(splc)) +
                     ",$," + step_str(b.id + "/roof") + "," + (flat ? ".FLAT_ROOF." : ".NOTDEFINED.") +
                     ")");
      aggregate(key + "/roof", roof, slabs);
      int qto = add("IFCELEMENTQUANTITY('" + ifc_guid(key + "/roof/qto") +
                    "',$,'Qto_RoofBaseQuantities',$,$,(" + ref(area_q("GrossArea", roof_area)) + "," +
                    ref(area_q("NetArea", roof_area)) + "," + ref(area_q("ProjectedArea", roof_plan)) +
                    "))");
      define(key + "/roof/qto/rel", roof, qto);
      contained.push_back(roof);
    }
    if (!contained.empty())
      add("IFCRELCONTAINEDINSPATIALSTRUCTURE('" + ifc_guid(key + "/contains") + "',$,$,$," +
          refs(contained) + "," + ref(storey) + ")");
  }

  // One IfcTriangulatedFaceSet for all faces of the element (vertices shared).
  int body(const Element& el) {
    std::map<std::array<double, 3>, int> index;
    std::string coords, tris;
    for (const auto& f : el.faces) {
      exp::Triangles t = exp::triangulate(f);
      std::vector<int> local(t.points.size());
      for (size_t i = 0; i < t.points.size(); ++i) {
        const Vec3& p = t.points[i];
        auto [it, fresh] = index.try_emplace({p.x(), p.y(), p.z()}, int(index.size()) + 1);
        if (fresh)
          coords += std::string(coords.empty() ? "" : ",") + "(" + step_real(p.x()) + "," +
                    step_real(p.y()) + "," + step_real(p.z()) + ")";
        local[i] = it->second;
      }
      for (const auto& tr : t.tris)
        tris += std::string(tris.empty() ? "" : ",") + "(" + std::to_string(local[tr[0]]) + "," +
                std::to_string(local[tr[1]]) + "," + std::to_string(local[tr[2]]) + ")";
    }
    if (tris.empty()) return 0;
    int pl = add("IFCCARTESIANPOINTLIST3D((" + coords + "))");
    int tfs = add("IFCTRIANGULATEDFACESET(" + ref(pl) + ",$,$,(" + tris + "),$)");
    int rep = add("IFCSHAPEREPRESENTATION(" + ref(body_) + ",'Body','Tessellation',(" + ref(tfs) + "))");
    return add("IFCPRODUCTDEFINITIONSHAPE($,$,(" + ref(rep) + "))");
  }

  int element(const Building& b, size_t e, int splc) {
    const Element& el = b.elements[e];
    const std::string tag = b.id + "/e" + std::to_string(e);
    const std::string key = "element/" + tag;
    int shape = body(el);
    if (!shape) return 0;
    std::string name = std::string(to_string(el.type)) + " " + std::to_string(e);
    std::string common = "('" + ifc_guid(key) + "',$," + step_str(name) + ",$,";
    std::string rest = ref(placement(splc)) + "," + ref(shape) + "," + step_str(tag) + ",";
    int id = 0;
    switch (el.type) {
      case ElementType::Roof: id = add("IFCSLAB" + common + "$," + rest + ".ROOF.)"); break;
      case ElementType::Ground: id = add("IFCSLAB" + common + "$," + rest + ".BASESLAB.)"); break;
      case ElementType::Wall: id = add("IFCWALL" + common + "$," + rest + ".SOLIDWALL.)"); break;
      case ElementType::PartyWall:
        id = add("IFCWALL" + common + "'PartyWall'," + rest + ".USERDEFINED.)");
        break;
      case ElementType::OuterCeiling:
        id = add("IFCCOVERING" + common + "$," + rest + ".CEILING.)");
        break;
    }
    quantities(el, key, id);
    properties(el, key, id);
    return id;
  }

  void quantities(const Element& el, const std::string& key, int id) {
    bool wall = el.type == ElementType::Wall || el.type == ElementType::PartyWall;
    std::vector<int> q = {area_q(wall ? "GrossSideArea" : "GrossArea", el.area),
                          area_q(wall ? "NetSideArea" : "NetArea", el.area)};
    if (el.type == ElementType::Roof) q.push_back(area_q("ProjectedArea", el.plan_area));
    int qto = add("IFCELEMENTQUANTITY('" + ifc_guid(key + "/qto") + "',$,'" + qto_name(el.type) +
                  "',$,$," + refs(q) + ")");
    define(key + "/qto/rel", id, qto);
  }

  void properties(const Element& el, const std::string& key, int id) {
    auto prop = [&](const char* name, const std::string& value) {
      return add(std::string("IFCPROPERTYSINGLEVALUE('") + name + "',$," + value + ",$)");
    };
    std::vector<int> p = {
        prop("ElementType", "IFCLABEL(" + step_str(to_string(el.type)) + ")"),
        prop("Area", "IFCAREAMEASURE(" + step_real(el.area) + ")"),
        prop("AreaSigma", "IFCAREAMEASURE(" + step_real(el.sigma_area) + ")"),
        prop("PlanArea", "IFCAREAMEASURE(" + step_real(el.plan_area) + ")"),
        prop("SlopeDegrees", "IFCREAL(" + step_real(el.slope_deg, 2) + ")"),
        prop("AzimuthDegrees", "IFCREAL(" + step_real(el.azimuth_deg, 2) + ")"),
        prop("SupportPoints", "IFCINTEGER(" + std::to_string(el.support_points) + ")"),
        prop("PlaneFitRMSE", "IFCLENGTHMEASURE(" + step_real(el.rmse) + ")"),
        prop("WallEvidence", "IFCLABEL(" + step_str(to_string(el.evidence)) + ")"),
        prop("IsPartyWall", el.type == ElementType::PartyWall ? "IFCBOOLEAN(.T.)" : "IFCBOOLEAN(.F.)")};
    int pset = add("IFCPROPERTYSET('" + ifc_guid(key + "/pset") +
                   "',$,'Cadastre3D_ElementMeasurement',$," + refs(p) + ")");
    define(key + "/pset/rel", id, pset);
  }
};

}  // namespace

void write_ifc(const BatchModel& model, const std::string& path) {
  std::ofstream os(path, std::ios::binary);
  if (!os) throw std::runtime_error(path + ": cannot open for writing");
  std::string name = path.substr(path.find_last_of('/') + 1);
  IfcWriter(os, model, name).run();
  if (!os) throw std::runtime_error(path + ": write failed");
}

}  // namespace c3d
