// IFC4 (ADD2 TC1) STEP writer, own text output: IfcProject -> IfcSite (per parcel)
// -> IfcBuilding -> one IfcBuildingStorey per storey; roof slabs aggregated in an
// IfcRoof; each element contained in the storey it belongs to (docs/exports.md,
// "IFC storeys"), with the IFC4 common property sets whose values we know.
// Geometry is one IfcTriangulatedFaceSet per element, relative to its storey's
// placement, in the frame of the frame origin, georeferenced by IfcMapConversion.
// GlobalIds are hashes of stable keys.
#include <algorithm>
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

// A wall starting this little below a storey level starts on it: the storey
// height is the eave height over a rounded storey count, so levels are approximate.
constexpr double kStoreyTolM = 0.05;

// Storey levels of a building: `count` storeys of equal height from the ground
// floor (terrain_z) to the eave, as Building::storeys counts them.
struct StoreyLevels {
  double base = 0, height = 0;
  int count = 1;
  explicit StoreyLevels(const Building& b)
      : base(b.terrain_z), count(std::max(1, b.storeys)) {
    height = b.eave_height > 0 ? b.eave_height / count : 0;
    if (height <= 0) count = 1;
  }
  double elevation(int k) const { return base + k * height; }
  int top() const { return count - 1; }
  // The storey whose level z lies in (clamped to the building's storeys).
  int at(double z) const {
    if (height <= 0) return 0;
    int k = int(std::floor((z - base + kStoreyTolM) / height));
    return std::clamp(k, 0, top());
  }
};

double element_min_z(const Element& el) {
  double z = INFINITY;
  for (const auto& f : el.faces)
    for (const auto& p : f.ring) z = std::min(z, p.z());
  return z;
}

// The storey an element belongs to: ground slab the lowest, roof and outer
// ceiling the top storey, a wall the storey where it starts.
int storey_of(const Element& el, const StoreyLevels& levels) {
  switch (el.type) {
    case ElementType::Ground: return 0;
    case ElementType::Roof:
    case ElementType::OuterCeiling: return levels.top();
    case ElementType::Wall:
    case ElementType::PartyWall: return levels.at(element_min_z(el));
  }
  return 0;
}

const char* common_pset(ElementType t) {
  switch (t) {
    case ElementType::Roof:
    case ElementType::Ground: return "Pset_SlabCommon";
    case ElementType::Wall:
    case ElementType::PartyWall: return "Pset_WallCommon";
    case ElementType::OuterCeiling: return "Pset_CoveringCommon";
  }
  return "";
}

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

// Entities are written as they come; only the site ids wait for the project's
// aggregation at the end.
class IfcWriter : public ExportWriter {
 public:
  IfcWriter(const BatchModel& header, const std::string& path)
      : path_(path), file_(path, std::ios::binary), os_(file_), frame_(header.frame), epsg_(header.epsg) {
    if (!file_) throw std::runtime_error(path + ": cannot open for writing");
    file_name_ = path.substr(path.find_last_of('/') + 1);
    this->header();
    project();
  }

  void add(const BatchModel& page) override {
    page_ = &page;
    for (const auto& r : page.results) sites_.push_back(site(r));
    if (!os_) throw std::runtime_error(path_ + ": write failed");
  }

  std::vector<std::string> finish() override {
    if (!sites_.empty()) aggregate("project", project_, sites_);
    os_ << "ENDSEC;\nEND-ISO-10303-21;\n";
    if (!file_.flush()) throw std::runtime_error(path_ + ": write failed");
    file_.close();
    return {path_};
  }

 private:
  const std::string path_;
  std::ofstream file_;
  std::ostream& os_;
  const LocalFrame frame_;
  const int epsg_;
  const BatchModel* page_ = nullptr;
  std::string file_name_;
  std::vector<int> sites_;
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
    if (epsg_ > 0) {
      int crs = add("IFCPROJECTEDCRS('EPSG:" + std::to_string(epsg_) + "',$,$,$,$,$,$)");
      const Vec3& o = frame_.origin;
      add("IFCMAPCONVERSION(" + ref(ctx) + "," + ref(crs) + "," + step_real(o.x(), 4) + "," +
          step_real(o.y(), 4) + "," + step_real(o.z(), 4) + ",1.,0.,1.)");
    }
  }

  // A placement relative to another (none: absolute), raised by z.
  int placement(int relative_to, double z = 0) {
    int axis = axis_;
    if (z != 0) {
      int at = add("IFCCARTESIANPOINT((0.,0.," + step_real(z) + "))");
      axis = add("IFCAXIS2PLACEMENT3D(" + ref(at) + ",$,$)");
    }
    return add("IFCLOCALPLACEMENT(" + (relative_to ? ref(relative_to) : std::string("$")) + "," +
               ref(axis) + ")");
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
        Vec2 l = frame_.to_local(r[i % r.size()]);
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
    const Parcel* p = exp::parcel_of(*page_, r);
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
    // Local z 0 is the building's 0.00 level: its height in the CRS is the frame
    // origin's, so storey elevations are local z.
    const double z0 = frame_.origin.z();
    int bldg = add("IFCBUILDING('" + ifc_guid(key) + "',$," + step_str(b.id) + ",$,$," + ref(plc) +
                   ",$,$,.ELEMENT.," + step_real(z0) + "," + step_real(z0 + b.terrain_z) + ",$)");
    building_sets(b, key, bldg);
    const StoreyLevels levels(b);
    std::vector<Storey> storeys;
    for (int k = 0; k < levels.count; ++k) {
      Storey s;
      s.elevation = levels.elevation(k);
      s.placement = placement(plc, s.elevation);
      const std::string name = k == 0 ? "Ground floor" : "Floor " + std::to_string(k);
      s.id = add("IFCBUILDINGSTOREY('" + ifc_guid(key + "/storey" + std::to_string(k)) + "',$," +
                 step_str(name) + ",$,$," + ref(s.placement) + ",$,$,.ELEMENT.," +
                 step_real(s.elevation) + ")");
      storeys.push_back(s);
    }
    std::vector<int> ids;
    for (const auto& s : storeys) ids.push_back(s.id);
    aggregate(key, bldg, ids);
    contents(b, key, levels, storeys);
    return bldg;
  }

  // Pset_BuildingCommon (BuildingID, NumberOfStoreys) and the base quantities we know.
  void building_sets(const Building& b, const std::string& key, int bldg) {
    std::vector<int> q = {
        add("IFCQUANTITYLENGTH('Height',$,$," + step_real(b.ridge_height) + ",$)"),
        add("IFCQUANTITYLENGTH('EavesHeight',$,$," + step_real(b.eave_height) + ",$)"),
        add("IFCQUANTITYVOLUME('GrossVolume',$,$," + step_real(b.volume) + ",$)")};
    double footprint = 0;
    for (const auto& e : b.elements) footprint += e.type == ElementType::Ground ? e.area : 0;
    if (footprint > 0) q.insert(q.begin() + 2, area_q("FootprintArea", footprint));
    int qto = add("IFCELEMENTQUANTITY('" + ifc_guid(key + "/qto") +
                  "',$,'Qto_BuildingBaseQuantities',$,$," + refs(q) + ")");
    define(key + "/qto/rel", bldg, qto);
    std::vector<int> p = {prop("BuildingID", "IFCIDENTIFIER(" + step_str(b.id) + ")"),
                          prop("NumberOfStoreys", "IFCINTEGER(" + std::to_string(b.storeys) + ")")};
    int pset = add("IFCPROPERTYSET('" + ifc_guid(key + "/common") + "',$,'Pset_BuildingCommon',$," +
                   refs(p) + ")");
    define(key + "/common/rel", bldg, pset);
  }

  struct Storey {
    int id = 0, placement = 0;
    double elevation = 0;
    std::vector<int> contained;
  };

  void contents(const Building& b, const std::string& key, const StoreyLevels& levels,
                std::vector<Storey>& storeys) {
    std::vector<int> slabs;
    double roof_area = 0, roof_plan = 0;
    bool flat = true;
    Storey& top = storeys[levels.top()];
    for (size_t e = 0; e < b.elements.size(); ++e) {
      const Element& el = b.elements[e];
      Storey& s = storeys[storey_of(el, levels)];
      if (el.type == ElementType::Roof) {  // in the IfcRoof, placed on the top storey
        int id = element(b, e, top.placement, top.elevation);
        if (!id) continue;
        slabs.push_back(id);
        roof_area += el.area;
        roof_plan += el.plan_area;
        flat = flat && el.slope_deg < 5;
      } else if (int id = element(b, e, s.placement, s.elevation)) {
        s.contained.push_back(id);
      }
    }
    if (!slabs.empty()) top.contained.push_back(roof(b, key, top.placement, slabs, flat, roof_area, roof_plan));
    for (size_t k = 0; k < storeys.size(); ++k)
      if (!storeys[k].contained.empty())
        add("IFCRELCONTAINEDINSPATIALSTRUCTURE('" + ifc_guid(key + "/contains" + std::to_string(k)) +
            "',$,$,$," + refs(storeys[k].contained) + "," + ref(storeys[k].id) + ")");
  }

  // The IfcRoof aggregating the roof slabs, with its quantities and Pset_RoofCommon.
  int roof(const Building& b, const std::string& key, int plc, const std::vector<int>& slabs, bool flat,
           double area, double plan) {
    int roof = add("IFCROOF('" + ifc_guid(key + "/roof") + "',$,'Roof',$,$," + ref(placement(plc)) +
                   ",$," + step_str(b.id + "/roof") + "," + (flat ? ".FLAT_ROOF." : ".NOTDEFINED.") + ")");
    aggregate(key + "/roof", roof, slabs);
    int qto = add("IFCELEMENTQUANTITY('" + ifc_guid(key + "/roof/qto") +
                  "',$,'Qto_RoofBaseQuantities',$,$,(" + ref(area_q("GrossArea", area)) + "," +
                  ref(area_q("NetArea", area)) + "," + ref(area_q("ProjectedArea", plan)) + "))");
    define(key + "/roof/qto/rel", roof, qto);
    int pset = add("IFCPROPERTYSET('" + ifc_guid(key + "/roof/common") + "',$,'Pset_RoofCommon',$,(" +
                   ref(prop("IsExternal", "IFCBOOLEAN(.T.)")) + "))");
    define(key + "/roof/common/rel", roof, pset);
    return roof;
  }

  // One IfcTriangulatedFaceSet for all faces of the element (vertices shared),
  // z relative to the storey level `dz`.
  int body(const Element& el, double dz) {
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
                    step_real(p.y()) + "," + step_real(p.z() - dz) + ")";
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

  // The element placed on the storey placement `plc` at level `dz`.
  int element(const Building& b, size_t e, int plc, double dz) {
    const Element& el = b.elements[e];
    const std::string tag = b.id + "/e" + std::to_string(e);
    const std::string key = "element/" + tag;
    int shape = body(el, dz);
    if (!shape) return 0;
    std::string name = std::string(to_string(el.type)) + " " + std::to_string(e);
    std::string common = "('" + ifc_guid(key) + "',$," + step_str(name) + ",$,";
    std::string rest = ref(placement(plc)) + "," + ref(shape) + "," + step_str(tag) + ",";
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
    common_properties(el, key, id);
    properties(el, key, id);
    return id;
  }

  // Base quantities as IFC4 defines them for the type: the element's area
  // (Qto_SlabBaseQuantities has no projected area: it is in our own set).
  void quantities(const Element& el, const std::string& key, int id) {
    bool wall = el.type == ElementType::Wall || el.type == ElementType::PartyWall;
    std::vector<int> q = {area_q(wall ? "GrossSideArea" : "GrossArea", el.area),
                          area_q(wall ? "NetSideArea" : "NetArea", el.area)};
    int qto = add("IFCELEMENTQUANTITY('" + ifc_guid(key + "/qto") + "',$,'" + qto_name(el.type) +
                  "',$,$," + refs(q) + ")");
    define(key + "/qto/rel", id, qto);
  }

  // The common property set of the type, with what we know: every element is
  // part of the envelope, so IsExternal is true (a party wall too: IFC4 calls a
  // boundary with another building on the other side external, EXTERNAL_FIRE);
  // a roof slab's PitchAngle is its slope (radians, the project's angle unit).
  void common_properties(const Element& el, const std::string& key, int id) {
    std::vector<int> p = {prop("IsExternal", "IFCBOOLEAN(.T.)")};
    if (el.type == ElementType::Roof)
      p.push_back(prop("PitchAngle", "IFCPLANEANGLEMEASURE(" + step_real(el.slope_deg * M_PI / 180, 6) + ")"));
    int pset = add("IFCPROPERTYSET('" + ifc_guid(key + "/common") + "',$,'" + common_pset(el.type) + "',$," +
                   refs(p) + ")");
    define(key + "/common/rel", id, pset);
  }

  int prop(const char* name, const std::string& value) {
    return add(std::string("IFCPROPERTYSINGLEVALUE('") + name + "',$," + value + ",$)");
  }
  void properties(const Element& el, const std::string& key, int id) {
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

std::unique_ptr<ExportWriter> ifc_writer(const BatchModel& header, const std::string& path) {
  return std::make_unique<IfcWriter>(header, path);
}

void write_ifc(const BatchModel& model, const std::string& path) {
  auto w = ifc_writer(model, path);
  w->add(model);
  w->finish();
}

}  // namespace c3d
