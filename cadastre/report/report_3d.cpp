// The report's 3D view: the parcel page's scene and the summary's cells (report_3d.h).
#include "cadastre/report/report_3d.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "cadastre/report/report_parts.h"
#include "core/error.h"
#include "core/mesh/mesh_files.h"
#include "ifc_citygml/detail.h"
#include "ifc_citygml/spool.h"

namespace fs = std::filesystem;

namespace c3d::report_detail {

using nlohmann::json;

namespace {

double mm(double v) { return std::round(v * 1000) / 1000; }

// A face's triangles, vertex after vertex, less `centre`, to the mm.
void add_triangles(const Face& face, const Vec3& centre, std::vector<double>& out) {
  const exp::Triangles t = exp::triangulate(face);
  for (const auto& tri : t.tris)
    for (int k : tri)
      for (int d = 0; d < 3; ++d) out.push_back(mm(t.points[size_t(k)][d] - centre[d]));
}

// A parcel's polygons as rings of x, y (local, less `centre`), outer first.
json rings(const Parcel& p, const LocalFrame& frame, const Vec2& centre) {
  json polys = json::array();
  for (const Polygon2& poly : p.shape) {
    json rs = json::array();
    auto ring = [&](const std::vector<Vec2>& pts) {
      std::vector<double> flat;
      for (const Vec2& q : pts) {
        const Vec2 l = frame.to_local(q) - centre;
        flat.insert(flat.end(), {mm(l.x()), mm(l.y())});
      }
      rs.push_back(flat);
    };
    ring(poly.outer);
    for (const auto& hole : poly.holes) ring(hole);
    polys.push_back(rs);
  }
  return polys;
}

// The ground under a parcel: its lowest building's floor, NaN without one.
double ground_of(const ParcelResult& r) {
  double z = kNaN;
  for (const Building& b : r.buildings) z = std::isnan(z) ? b.terrain_z : std::min(z, b.terrain_z);
  return z;
}

json element_types() {
  json types = json::array();
  for (ElementType t : kTypes) types[size_t(t)] = {{"name", label(t)}, {"colour", colour(t)}};
  return types;
}

// JSON inside a <script>: "</" would end the script.
std::string script_safe(std::string s) {
  for (size_t at = 0; (at = s.find("</", at)) != std::string::npos; at += 3) s.replace(at, 2, "<\\/");
  return s;
}

std::string data_script(const std::string& name, const json& value) {
  return "C3DViewer.data(" + json(name).dump() + "," + script_safe(value.dump()) + ");\n";
}

void write_file(const fs::path& path, std::string_view text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw InputError(path.string(), "cannot write report");
}

std::string cell_name(std::pair<long, long> c) { return "cell_" + std::to_string(c.first) + "_" + std::to_string(c.second); }

// Where a parcel page's scene has its origin: the parcel's centre (mean of
// its outline's vertices) on the ground of its lowest building.
Vec3 scene_centre(const Parcel& p, const ParcelResult& r, const LocalFrame& frame) {
  Vec2 mid(0, 0);
  size_t n = 0;
  for (const Polygon2& poly : p.shape)
    for (const Vec2& q : poly.outer) mid += frame.to_local(q), ++n;
  if (n) mid /= double(n);
  const double z = ground_of(r);
  return {mid.x(), mid.y(), std::isnan(z) ? 0.0 : z};
}

std::string level_name(const MeshLevelRecord& l) { return fs::path(l.ply).stem().string(); }

// The mesh levels a parcel page offers: those with faces.
json mesh_levels(const ParcelResult& r, const std::string& to_report) {
  json levels = json::array();
  for (size_t bi = 0; bi < r.buildings.size(); ++bi)
    for (const MeshLevelRecord& l : r.buildings[bi].mesh.levels)
      if (!l.glb.empty())
        levels.push_back({{"b", bi}, {"level", l.level}, {"faces", l.faces}, {"mean", l.mean_m}, {"p95", l.p95_m},
                          {"closed", l.closed}, {"name", level_name(l)},
                          {"file", to_report + "3d/mesh/" + level_name(l) + ".js"}});
  return levels;
}

}  // namespace

size_t SummaryCells::Colouring::of(const std::string& status, double value) const {
  const size_t failed = classes->count();  // then suspect, then not valued
  return status == "failed" ? failed : status == "suspect" ? failed + 1 : value < 0 ? failed + 2 : classes->of(value);
}

void write_mesh_levels(const ParcelResult& r, const Parcel& p, const LocalFrame& frame,
                       const std::string& files_root, const std::string& out_dir) {
  if (files_root.empty()) return;
  const Vec3 centre = frame.to_world(scene_centre(p, r, frame));
  const fs::path dir = fs::path(out_dir) / "report" / "3d" / "mesh";
  for (const Building& b : r.buildings)
    for (const MeshLevelRecord& l : b.mesh.levels) {
      std::error_code ec;
      const fs::path ply = fs::path(files_root) / l.ply;
      if (l.glb.empty() || !fs::is_regular_file(ply, ec)) continue;
      const TriMesh mesh = read_local_ply(ply.string());
      std::vector<double> pos;
      std::vector<int> idx;
      for (const Vec3& v : mesh.vertices)
        for (int d = 0; d < 3; ++d) pos.push_back(mm(v[d] - centre[d]));
      for (const auto& t : mesh.triangles) idx.insert(idx.end(), t.begin(), t.end());
      fs::create_directories(dir, ec);
      write_file(dir / (level_name(l) + ".js"), data_script(level_name(l), {{"pos", pos}, {"idx", idx}}));
    }
}

std::string parcel_view(const Parcel& p, const ParcelResult& r, const ParcelValuation* v,
                        const LocalFrame& frame, const std::string& to_report) {
  const Vec3 centre = scene_centre(p, r, frame);
  json buildings = json::array();
  for (const Building& b : r.buildings) {
    json elements = json::array();
    for (size_t i = 0; i < b.elements.size(); ++i) {
      const Element& e = b.elements[i];
      std::vector<double> tri;
      for (const Face& f : e.faces) add_triangles(f, centre, tri);
      const bool wall = e.type == ElementType::Wall || e.type == ElementType::PartyWall;
      elements.push_back({{"t", int(e.type)}, {"a", e.area}, {"s", e.sigma_area}, {"pa", e.plan_area},
                          {"sl", e.slope_deg}, {"n", e.support_points}, {"r", e.rmse},
                          {"ev", wall ? to_string(e.evidence) : ""}, {"m", element_amount(v, b.id, int(i))}, {"tri", tri}});
    }
    buildings.push_back({{"id", b.id}, {"lod", to_string(b.lod)}, {"elements", elements}});
  }
  const json scene = {{"types", element_types()}, {"currency", v ? v->currency : ""},
                      {"parcel", rings(p, frame, centre.head<2>())}, {"ground", 0.0}, {"buildings", buildings},
                      {"meshes", mesh_levels(r, to_report)}};
  return "<div class=\"view3d screen-only\" id=\"view3d\"></div><script src=\"" + to_report +
         "lib/c3d-viewer.js\"></script><script>C3DViewer.parcel(document.getElementById('view3d')," +
         script_safe(scene.dump()) + ");</script>";
}

std::string summary_view() {
  return std::string("<div class=\"view3d screen-only\" id=\"view3d\"></div><script src=\"") + kViewerScript +
         "\"></script><script>C3DViewer.summary(document.getElementById('view3d'),'" + kSummaryData +
         "');</script>";
}

SummaryCells::SummaryCells(const std::string& out_dir)
    : out_(out_dir), dir_((fs::path(out_dir) / "report" / "3d").string()) {
  std::error_code ec;
  fs::remove_all(dir_, ec);  // an earlier report's cells
  fs::create_directories(fs::path(dir_) / "spool", ec);
}

// A parcel's record in its cell's spool: its figures, ground and rings, and
// its buildings' triangles near (by element) and far (the prism).
void SummaryCells::add(const Parcel& p, const ParcelResult& r, const ParcelValuation* v, const LocalFrame& frame) {
  const Vec3 centre = scene_centre(p, r, frame);
  const std::pair<long, long> cell{long(std::floor(centre.x() / kCellM)), long(std::floor(centre.y() / kCellM))};
  const double z = ground_of(r);
  if (!std::isnan(z)) ground_z_.push_back(z);
  Eigen::AlignedBox3d& box = boxes_[cell];
  json buildings = json::array();
  for (const Building& b : r.buildings) {
    std::vector<double> near, far;
    for (const Element& e : b.elements)
      for (const Face& f : e.faces) add_triangles(f, Vec3::Zero(), near);
    if (const LodShell* prism = lower_lod(b, Lod::Lod12))  // the far stand-in, else its own faces
      for (const Face& f : prism->faces) add_triangles(f, Vec3::Zero(), far);
    else
      far = near;
    for (size_t i = 0; i + 2 < near.size(); i += 3) box.extend(Vec3(near[i], near[i + 1], near[i + 2]));
    buildings.push_back({{"id", b.id}, {"near", near}, {"far", far}});
  }
  const json record = {{"id", p.id}, {"page", parcel_page(p)}, {"status", to_string(r.status)},
                       {"v", std::isfinite(njop_per_m2(v)) ? njop_per_m2(v) : -1.0},
                       {"z", std::isnan(z) ? json(nullptr) : json(mm(z))}, {"rings", rings(p, frame, Vec2::Zero())},
                       {"buildings", buildings}};
  exp::append_record((fs::path(dir_) / "spool" / cell_name(cell)).string(), json::to_msgpack(record));
}

void SummaryCells::write_cell(std::pair<long, long> cell, Eigen::AlignedBox3d& box, const Colouring& colouring) const {
  json parcels_far = json::array(), parcels_near = json::array(), buildings = json::array();
  std::vector<double> far, near;
  std::vector<size_t> far_counts, near_counts;
  exp::read_records((fs::path(dir_) / "spool" / cell_name(cell)).string(), [&](const std::vector<std::uint8_t>& bytes) {
    const json p = json::from_msgpack(bytes);
    const double z = p["z"].is_null() ? colouring.ground : p["z"].get<double>();
    for (const auto& poly : p["rings"])
      for (const auto& ring : poly)
        for (size_t i = 0; i + 1 < ring.size(); i += 2) box.extend(Vec3(ring[i], ring[i + 1], z));
    json figures = {{"id", p["id"]}, {"page", p["page"]}, {"status", p["status"]}, {"v", p["v"]},
                    {"c", colouring.of(p["status"], p["v"])}};
    parcels_near.push_back(figures);
    figures["z"] = z, figures["rings"] = p["rings"];
    parcels_far.push_back(figures);
    for (const json& b : p["buildings"]) {
      buildings.push_back({{"id", b["id"]}, {"p", parcels_near.size() - 1}});
      const auto n = b["near"].get<std::vector<double>>(), f = b["far"].get<std::vector<double>>();
      near.insert(near.end(), n.begin(), n.end()), near_counts.push_back(n.size() / 9);
      far.insert(far.end(), f.begin(), f.end()), far_counts.push_back(f.size() / 9);
    }
  });
  const std::string name = cell_name(cell);
  write_file(fs::path(dir_) / (name + "-far.js"),
             data_script(name + "-far", {{"parcels", parcels_far}, {"buildings", buildings},
                                         {"prisms", {{"pos", far}, {"counts", far_counts}}}}));
  write_file(fs::path(dir_) / (name + ".js"),
             data_script(name, {{"parcels", parcels_near}, {"buildings", buildings},
                                {"elements", {{"pos", near}, {"counts", near_counts}}}}));
}

void SummaryCells::finish(const ValueClasses& classes, const std::string& currency) {
  // Colours: the value classes, then failed, suspect and not valued (as the map draws them).
  json colours = json::array(), labels = json::array();
  for (size_t k = 0; k < classes.count(); ++k) colours.push_back(classes.colour(k)), labels.push_back(classes.label(k));
  colours.insert(colours.end(), {"#e57373", "#ffb74d", "#ffffff"});
  labels.insert(labels.end(), {"failed, land only", "suspect, land only", "not valued"});
  std::sort(ground_z_.begin(), ground_z_.end());
  const Colouring colouring{&classes, ground_z_.empty() ? 0 : ground_z_[ground_z_.size() / 2]};
  json cells = json::array();
  for (auto& [cell, box] : boxes_) {
    write_cell(cell, box, colouring);
    cells.push_back({{"name", cell_name(cell)}, {"box", {box.min().x(), box.min().y(), box.min().z(), box.max().x(),
                                                         box.max().y(), box.max().z()}}});
  }
  std::error_code ec;
  fs::remove_all(fs::path(dir_) / "spool", ec);
  // Near: by element within 300 m of the camera (a street's length), prisms beyond.
  write_file(fs::path(dir_) / "index.js",
             data_script("index", {{"cells", cells}, {"colours", colours}, {"labels", labels},
                                   {"currency", currency}, {"pages", "report/"}, {"near_m", 300}}));
  const fs::path lib = fs::path(out_) / kViewerScript;
  fs::create_directories(lib.parent_path(), ec);
  write_file(lib, viewer_script());
}

}  // namespace c3d::report_detail
