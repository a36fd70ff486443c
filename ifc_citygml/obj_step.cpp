// OBJ per parcel (one group per element, triangulated, local coordinates, with
// the offset and CRS in files beside it) and a STEP B-rep solid per building
// through OpenCASCADE: a curved building's exact solid (its cylinders,
// spheres, cones and surfaces of revolution), any other's faces sewn into a
// shell.
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakePolygon.hxx>
#include <BRepBuilderAPI_MakeSolid.hxx>
#include <BRepBuilderAPI_Sewing.hxx>
#include <BRepLib.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_Printer.hxx>
#include <STEPControl_Controller.hxx>
#include <STEPControl_Writer.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shell.hxx>
#include <TopoDS_Solid.hxx>
#include <TopoDS_Wire.hxx>
#include <gp_Dir.hxx>
#include <gp_Pln.hxx>
#include <gp_Pnt.hxx>

#include <cpl_conv.h>
#include <ogr_spatialref.h>

#include <cctype>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <utility>

#include "core/geometry/geometry.h"
#include "core/io/file_names.h"
#include "core/primitives/exact_solid.h"
#include "ifc_citygml/detail.h"
#include "ifc_citygml/export.h"

namespace fs = std::filesystem;

namespace c3d {
namespace {

// An OBJ object or group name (not a file name: see file_stem_for_id).
std::string obj_name(const std::string& s) {
  std::string out;
  for (char c : s) out += (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '.' || c == '_') ? c : '_';
  return out.empty() ? "unnamed" : out;
}

// The model's CRS as ESRI WKT (the .prj dialect GIS tools read), or "" when unknown.
std::string esri_wkt(const BatchModel& m) {
  OGRSpatialReference srs;
  const bool ok = m.epsg > 0 ? srs.importFromEPSG(m.epsg) == OGRERR_NONE
                             : !m.crs_wkt.empty() && srs.SetFromUserInput(m.crs_wkt.c_str()) == OGRERR_NONE;
  if (!ok) return "";
  char* out = nullptr;
  const char* opts[] = {"FORMAT=WKT1_ESRI", nullptr};
  std::string wkt = srs.exportToWkt(&out, opts) == OGRERR_NONE && out ? out : "";
  CPLFree(out);
  return wkt;
}

// Beside <stem>.obj: <stem>.offset.json (world = local + offset, CRS) and, when
// the CRS is known, <stem>.prj (docs/exports.md, "OBJ").
void write_georeference(const BatchModel& m, const fs::path& obj, const std::string& prj) {
  const Vec3& o = m.frame.origin;
  nlohmann::json j = {{"obj", obj.filename().string()},
                      {"offset", {o.x(), o.y(), o.z()}},
                      {"world", "local + offset"},
                      {"units", "metre"},
                      {"crs", m.epsg > 0 ? nlohmann::json("EPSG:" + std::to_string(m.epsg)) : nlohmann::json()},
                      {"crs_wkt", m.crs_wkt}};
  fs::path json = obj;
  json.replace_extension(".offset.json");
  std::ofstream(json) << j.dump(2) << "\n";
  if (prj.empty()) return;
  fs::path p = obj;
  p.replace_extension(".prj");
  std::ofstream(p) << prj << "\n";
}

void write_obj(const BatchModel& m, const ParcelResult& r, const std::string& path) {
  std::ofstream os(path, std::ios::binary);
  if (!os) throw std::runtime_error(path + ": cannot open for writing");
  const Vec3& o = m.frame.origin;
  fs::path json = fs::path(path).filename();
  json.replace_extension(".offset.json");
  os << "# Cadastre3D parcel " << r.parcel_id << "\n# coordinates local: world = local + ("
     << exp::fixed(o.x(), 3) << ", " << exp::fixed(o.y(), 3) << ", " << exp::fixed(o.z(), 3)
     << ")" << (m.epsg > 0 ? ", EPSG:" + std::to_string(m.epsg) : std::string()) << "\n"
     << "# georeference: " << json.string() << " (offset and CRS)\n";
  long base = 1;  // OBJ indices are 1-based and file-global
  for (const auto& b : r.buildings) {
    os << "o " << obj_name(b.id) << "\n";
    for (size_t e = 0; e < b.elements.size(); ++e) {
      const Element& el = b.elements[e];
      os << "g " << obj_name(b.id) << "_" << to_string(el.type) << "_" << e << "\n";
      for (const auto& f : el.faces) {
        exp::Triangles t = exp::triangulate(f);
        for (const auto& p : t.points)
          os << "v " << exp::fixed(p.x(), 4) << ' ' << exp::fixed(p.y(), 4) << ' '
             << exp::fixed(p.z(), 4) << "\n";
        for (const auto& tr : t.tris)
          os << "f " << base + tr[0] << ' ' << base + tr[1] << ' ' << base + tr[2] << "\n";
        base += long(t.points.size());
      }
    }
  }
  if (!os) throw std::runtime_error(path + ": write failed");
}

TopoDS_Wire occ_wire(const Ring3& ring) {
  BRepBuilderAPI_MakePolygon poly;
  for (const auto& p : ring) poly.Add(gp_Pnt(p.x(), p.y(), p.z()));
  poly.Close();
  if (!poly.IsDone()) throw std::runtime_error("degenerate ring");
  return poly.Wire();
}

// Sewn closed solid of the building's shell faces; throws when it cannot be made.
TopoDS_Shape occ_solid(const Building& b) {
  BRepBuilderAPI_Sewing sew(1e-3);
  for (const auto& f : b.solid) {
    TopoDS_Wire outer = occ_wire(f.ring);
    BRepBuilderAPI_MakeFace mk(outer, /*OnlyPlane=*/true);
    if (!mk.IsDone()) {  // planar only within our tolerance: put it on its mean plane
      Vec3 n = unit_normal(f), c = Vec3::Zero();
      for (const auto& p : f.ring) c += p;
      c /= double(f.ring.size());
      mk = BRepBuilderAPI_MakeFace(gp_Pln(gp_Pnt(c.x(), c.y(), c.z()), gp_Dir(n.x(), n.y(), n.z())),
                                   outer, /*Inside=*/true);
    }
    for (size_t k = 0; k < f.holes.size() && mk.IsDone(); ++k) {
      TopoDS_Wire w = occ_wire(exp::hole_oriented(f, k));
      mk.Add(w);
    }
    if (!mk.IsDone()) throw std::runtime_error("face not planar");
    sew.Add(mk.Face());
  }
  sew.Perform();
  TopoDS_Shape sewn = sew.SewedShape();
  TopExp_Explorer ex(sewn, TopAbs_SHELL);
  if (!ex.More()) throw std::runtime_error("faces do not sew into a shell");
  BRepBuilderAPI_MakeSolid ms(TopoDS::Shell(ex.Current()));
  if (!ms.IsDone()) throw std::runtime_error("shell does not make a solid");
  TopoDS_Solid solid = ms.Solid();
  BRepLib::OrientClosedSolid(solid);  // outward normals, whatever sewing chose
  return solid;
}

// The STEP writer reports every file on stdout; quiet it while we write, then restore.
class QuietOcc {
 public:
  QuietOcc() {
    for (const auto& p : Message::DefaultMessenger()->Printers()) {
      saved_.push_back(p->GetTraceLevel());
      p->SetTraceLevel(Message_Fail);
    }
  }
  ~QuietOcc() {
    size_t i = 0;
    for (const auto& p : Message::DefaultMessenger()->Printers())
      if (i < saved_.size()) p->SetTraceLevel(saved_[i++]);
  }

 private:
  std::vector<Message_Gravity> saved_;
};

}  // namespace

std::vector<std::string> write_obj_per_parcel(const BatchModel& model, const std::string& dir) {
  fs::create_directories(dir);
  std::vector<std::string> files;
  const std::string prj = esri_wkt(model);
  for (const auto& r : model.results) {
    if (r.buildings.empty()) continue;
    std::string path = (fs::path(dir) / (file_stem_for_id(r.parcel_id) + ".obj")).string();
    write_obj(model, r, path);
    write_georeference(model, path, prj);
    files.push_back(path);
  }
  return files;
}

std::vector<std::string> write_step_per_building(const BatchModel& model, const std::string& dir,
                                                 std::vector<std::string>* skipped) {
  fs::create_directories(dir);
  std::vector<std::string> files;
  QuietOcc quiet;
  // The STEP parameters exist only once the controller has registered them
  // (set before, they fail and the file said millimetres over metre values).
  // The session unit is metres too, so the writer scales nothing.
  STEPControl_Controller::Init();
  for (const auto& [name, value] : {std::pair<const char*, const char*>{"xstep.cascade.unit", "M"},
                                    {"write.step.unit", "M"},
                                    {"write.step.schema", "AP214IS"}})
    if (!Interface_Static::SetCVal(name, value))
      throw std::runtime_error(std::string("OpenCASCADE refused the STEP setting ") + name);
  for (const auto& r : model.results) {
    for (const auto& b : r.buildings) {
      if (b.solid.empty()) continue;
      TopoDS_Shape solid;
      try {
        solid = b.exact.parts.empty() ? occ_solid(b) : exact_solid(b.exact);
      } catch (const std::exception& e) {
        if (!skipped) throw std::runtime_error("building " + b.id + ": " + e.what());
        skipped->push_back(b.id + ": " + e.what());
        continue;
      }
      STEPControl_Writer writer;
      if (writer.Transfer(solid, STEPControl_AsIs) != IFSelect_RetDone)
        throw std::runtime_error("building " + b.id + ": STEP transfer failed");
      std::string path = (fs::path(dir) / (file_stem_for_id(b.id) + ".step")).string();
      if (writer.Write(path.c_str()) != IFSelect_RetDone)
        throw std::runtime_error(path + ": cannot write");
      files.push_back(path);
    }
  }
  return files;
}

}  // namespace c3d
