// cadastre3d evaluate: deviation of classified points from a building model
// (OBJ/PLY, or CityJSON), as the plane-intersection paper measures it: roof points against the
// roof surfaces (3D and vertical distance), wall points against the walls; per
// parcel when a parcel layer is given, and pooled.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <numeric>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cadastre/clip.h"
#include "cadastre/parcels.h"
#include "cli/commands.h"
#include "core/io/crs.h"
#include "core/error.h"
#include "core/evaluate/evaluate.h"
#include "core/geometry/geometry.h"
#include "core/io/mesh_io.h"
#include "core/io/point_io.h"
#include "ifc_citygml/export.h"

namespace c3d::cli {
namespace {

struct EvalOptions {
  std::vector<std::string> meshes;
  std::string cloud, classes = "roof=6,wall=64", parcels, id_field, json, residuals;
  double buffer = kWallPointReachM;
};

enum Kind { kRoof = 0, kWall = 1, kOther = 2 };

// "roof=6,wall=64" (a kind may repeat: roof=6,roof=7).
ClassMapping parse_classes(const std::string& s) {
  ClassMapping m;
  m.roof.clear();
  m.wall.clear();
  std::stringstream in(s);
  std::string item;
  while (std::getline(in, item, ',')) {
    auto eq = item.find('=');
    if (eq == std::string::npos) throw InputError("--classes", "expected kind=code, got '" + item + "'");
    const std::string kind = item.substr(0, eq);
    const int code = std::stoi(item.substr(eq + 1));
    if (kind == "roof") m.roof.push_back(code);
    else if (kind == "wall") m.wall.push_back(code);
    else throw InputError("--classes", "unknown kind '" + kind + "' (roof or wall)");
  }
  return m;
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

// Roof or wall by the group/material label an exporter gives, else by the normal
// (upward-facing and below 80 deg slope: roof; near vertical: wall).
Kind kind_of(const MeshGroup& g, const Face& f) {
  const std::string label = lower(g.name + " " + g.material);
  if (label.find("roof") != std::string::npos) return kRoof;
  if (label.find("wall") != std::string::npos) return kWall;
  if (label.find("ground") != std::string::npos || label.find("floor") != std::string::npos ||
      label.find("ceiling") != std::string::npos)
    return kOther;
  const double nz = unit_normal(f).z();
  if (nz > 0.17) return kRoof;
  return std::abs(nz) <= 0.17 ? kWall : kOther;
}

// One evaluation zone: a parcel, or everything when no parcels are given.
struct Zone {
  std::string id;
  std::vector<Face> faces[2];
  std::unique_ptr<FaceIndex> index[2];
  std::vector<Vec3> measured[2];  // the points behind dist[k], in the same order
  std::vector<double> dist[2], vertical;
  std::vector<double> own_roof, other_roof;  // over/under each wall point: see WallCover
  long unmodelled[2] = {0, 0};
};

// The parcel a group's faces belong to: its name starts with "<parcel id>_"
// (building ids are "<parcel id>_b<k>"), else the parcel under the face centroid.
int zone_of(const MeshGroup& g, const Face& f, const ParcelLayer& layer, const ParcelClipper& clip) {
  int best = -1;
  size_t best_len = 0;
  for (size_t p = 0; p < layer.parcels.size(); ++p) {
    const std::string& id = layer.parcels[p].id;
    if (id.size() > best_len && g.name.compare(0, id.size(), id) == 0 &&
        (g.name.size() == id.size() || g.name[id.size()] == '_')) {
      best = int(p);
      best_len = id.size();
    }
  }
  if (best >= 0) return best;
  Vec3 c = Vec3::Zero();
  for (const auto& p : f.ring) c += p;
  c /= double(f.ring.size());
  for (size_t p = 0; p < layer.parcels.size(); ++p)
    if (clip.inside(p, c.x(), c.y())) return int(p);
  auto lists = clip.clip(std::vector<Vec3>{c});  // in a buffer only
  for (size_t p = 0; p < lists.size(); ++p)
    if (!lists[p].empty()) return int(p);
  return -1;
}

// The points each zone measures: roof points inside the parcel, wall points
// within its buffer; every point when there are no parcels.
ParcelClipper::IndexLists points_of_zones(const std::vector<Vec3>& P, bool inside_only,
                                          const ParcelClipper* clipper) {
  ParcelClipper::IndexLists lists;
  if (!clipper) {
    lists.assign(1, std::vector<size_t>(P.size()));
    std::iota(lists[0].begin(), lists[0].end(), size_t(0));
    return lists;
  }
  lists = clipper->clip(P);
  if (inside_only)
    for (size_t z = 0; z < lists.size(); ++z)
      lists[z].erase(std::remove_if(lists[z].begin(), lists[z].end(),
                                    [&](size_t i) { return !clipper->inside(z, P[i].x(), P[i].y()); }),
                     lists[z].end());
  return lists;
}

std::string fixed(double v, int digits = 3) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

nlohmann::json to_json(const Deviation& d) {
  return {{"n", d.n}, {"mean", d.mean}, {"std", d.std}, {"rmse", d.rmse}, {"max", d.max}};
}

// "a roof within 0.3 m": the printed name of the part on the model, from the
// same constant the split uses.
std::string within_on_model(const char* surface) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "a %s within %.1f m", surface, kOnModelM);
  return buf;
}
const char* const kRoofPartKeys[] = {"on_model", "off_model", "uncovered"};
const char* const kWallPartKeys[] = {"on_wall", "under_own_roof", "under_other_roof", "under_no_roof"};

nlohmann::json to_json(const char* const* keys, const std::vector<Deviation>& parts) {
  nlohmann::json j;
  for (size_t k = 0; k < parts.size(); ++k) j[keys[k]] = to_json(parts[k]);
  return j;
}

std::vector<Deviation> pool_parts(const std::vector<std::vector<Deviation>>& per_zone) {
  std::vector<Deviation> pooled;
  for (size_t k = 0; !per_zone.empty() && k < per_zone.front().size(); ++k) {
    std::vector<Deviation> part;
    for (const auto& z : per_zone) part.push_back(z[k]);
    pooled.push_back(pool(part));
  }
  return pooled;
}

// Where a pooled deviation comes from: each part's points and share of the
// squared distance.
void print_parts(const char* title, const std::vector<std::string>& labels, const std::vector<Deviation>& parts) {
  double total = 0;
  for (const Deviation& d : parts) total += double(d.n) * d.rmse * d.rmse;
  std::printf("%s (share of the squared distance):\n", title);
  for (size_t k = 0; k < parts.size(); ++k) {
    const Deviation& d = parts[k];
    const double share = total > 0 ? 100.0 * double(d.n) * d.rmse * d.rmse / total : 0.0;
    std::printf("  %-24s %8ld  rmse %6.3f  %5.1f %%\n", labels[k].c_str(), d.n, d.rmse, share);
  }
}

void print_row(const std::string& id, const Deviation& r, const Deviation& v, const Deviation& w) {
  auto cols = [](const Deviation& d) {
    char buf[128];
    if (d.n == 0) std::snprintf(buf, sizeof buf, "%8s %7s %7s %7s %7s", "0", "-", "-", "-", "-");
    else std::snprintf(buf, sizeof buf, "%8ld %7.3f %7.3f %7.3f %7.3f", d.n, d.mean, d.std, d.rmse, d.max);
    return std::string(buf);
  };
  char vbuf[32];
  std::snprintf(vbuf, sizeof vbuf, "%8s", v.n ? fixed(v.rmse).c_str() : "-");
  std::printf("%-22s %s %s  %s\n", id.c_str(), cols(r).c_str(), vbuf, cols(w).c_str());
}

// One row per measured point, so a disputed deviation can be looked at point by
// point (QGIS reads the CSV as a point layer by its x/y columns).
void write_residuals(const std::string& path, const std::vector<Zone>& zones) {
  std::ofstream out(path);
  out << "parcel,kind,x,y,z,distance_m,vertical_m,part\n";
  char buf[160];
  for (const auto& z : zones)
    for (int k : {kRoof, kWall})
      for (size_t i = 0; i < z.measured[k].size(); ++i) {
        const Vec3& p = z.measured[k][i];
        const double d = z.dist[k][i], v = k == kRoof ? z.vertical[i] : kNaN;
        std::snprintf(buf, sizeof buf, ",%s,%.3f,%.3f,%.3f,%.4f,", k == kRoof ? "roof" : "wall", p.x(), p.y(),
                      p.z(), d);
        out << z.id << buf;
        if (std::isfinite(v)) out << fixed(v, 4);
        out << "," << (k == kRoof ? kRoofPartKeys[roof_cover_part(v)]
                                  : kWallPartKeys[wall_cover_part(d, z.own_roof[i], z.other_roof[i])])
            << "\n";
      }
  if (!out) throw InputError(path, "cannot write");
}

// A CityJSON file's buildings as mesh groups in world coordinates, one per
// element, named "<parcel id>_<building id>_<element type>" (the parcel from
// the building's parcel_id attribute, where it has one), so that each element
// is measured for its own parcel, as the batch's OBJ groups are.
std::vector<MeshGroup> read_cityjson_groups(const std::string& path) {
  const BatchModel model = read_cityjson(path);
  std::vector<MeshGroup> groups;
  for (const auto& r : model.results)
    for (const auto& b : r.buildings)
      for (const auto& e : b.elements) {
        MeshGroup g;
        g.name = (r.parcel_id.empty() ? "" : r.parcel_id + "_") + b.id + "_" + to_string(e.type);
        for (Face f : e.faces) {
          for (auto& p : f.ring) p += model.frame.origin;
          for (auto& h : f.holes)
            for (auto& p : h) p += model.frame.origin;
          g.faces.push_back(std::move(f));
        }
        groups.push_back(std::move(g));
      }
  return groups;
}

void run_evaluate(const EvalOptions& o) {
  const ClassMapping classes = parse_classes(o.classes);
  std::vector<MeshGroup> mesh;
  for (const auto& path : o.meshes) {
    auto groups = lower_ext(path) == "json" ? read_cityjson_groups(path) : read_mesh_groups(path);
    mesh.insert(mesh.end(), groups.begin(), groups.end());
  }
  std::vector<PointCloud> clouds{read_point_cloud(o.cloud)};
  PointCloud& cloud = clouds[0];

  // Zones and their faces.
  ParcelLayer layer;
  std::unique_ptr<ParcelClipper> clipper;
  std::vector<Zone> zones;
  if (!o.parcels.empty()) {
    std::vector<std::string> warnings;
    layer = read_parcels(o.parcels, parcel_fields(o.id_field), &warnings);
    CrsReconciliation crs = reconcile_crs(layer, clouds);
    warnings.insert(warnings.end(), crs.warnings.begin(), crs.warnings.end());
    for (const auto& w : warnings) std::cerr << "cadastre3d: warning: " << w << "\n";
    ClipParams params;
    params.overhang_buffer_m = o.buffer;
    clipper = std::make_unique<ParcelClipper>(layer, params);
    zones.resize(layer.parcels.size());
    for (size_t p = 0; p < zones.size(); ++p) zones[p].id = layer.parcels[p].id;
  } else {
    zones.resize(1);
    zones[0].id = "all";
  }
  long faces_outside = 0;
  for (const auto& g : mesh)
    for (const auto& f : g.faces) {
      if (f.ring.size() < 3) continue;
      const Kind k = kind_of(g, f);
      if (k == kOther) continue;
      const int z = clipper ? zone_of(g, f, layer, *clipper) : 0;
      if (z < 0) ++faces_outside;
      else zones[size_t(z)].faces[k].push_back(f);
    }
  // FaceIndex works in its own local origin: world coordinates keep precision.
  for (auto& z : zones)
    for (int k : {kRoof, kWall})
      if (!z.faces[k].empty()) z.index[k] = std::make_unique<FaceIndex>(z.faces[k]);
  // Every zone's roofs, tagged by zone: whose roof stands over a wall point.
  std::unique_ptr<FaceIndex> all_roofs;
  if (zones.size() > 1) {
    std::vector<Face> faces;
    std::vector<int> owner;
    for (size_t z = 0; z < zones.size(); ++z) {
      faces.insert(faces.end(), zones[z].faces[kRoof].begin(), zones[z].faces[kRoof].end());
      owner.insert(owner.end(), zones[z].faces[kRoof].size(), int(z));
    }
    if (!faces.empty()) all_roofs = std::make_unique<FaceIndex>(faces, owner);
  }

  // Points by class. The batch's ruler: every roof point inside a parcel
  // against that parcel's roofs, every wall point within the buffer of a parcel
  // against that parcel's walls (so a wall point near two parcels counts for both).
  std::vector<Vec3> pts[2];
  const bool unclassified = cloud.classes.empty();
  for (size_t i = 0; i < cloud.points.size(); ++i) {
    const int c = unclassified ? classes.roof.front() : cloud.classes[i];
    if (std::count(classes.roof.begin(), classes.roof.end(), c)) pts[kRoof].push_back(cloud.points[i]);
    else if (std::count(classes.wall.begin(), classes.wall.end(), c)) pts[kWall].push_back(cloud.points[i]);
  }
  if (unclassified) std::cerr << "cadastre3d: note: " << o.cloud << " has no classes; all points taken as roof\n";
  long outside = 0;
  for (int k : {kRoof, kWall}) {
    const auto& P = pts[k];
    const auto lists = points_of_zones(P, k == kRoof, clipper.get());
    std::vector<char> counted(P.size(), 0);
    for (size_t z = 0; z < zones.size(); ++z) {
      if (lists[z].empty()) continue;
      for (size_t i : lists[z]) counted[i] = 1;
      if (!zones[z].index[k]) {
        zones[z].unmodelled[k] += long(lists[z].size());
        continue;
      }
      std::vector<Vec3> sub;
      for (size_t i : lists[z]) sub.push_back(P[i]);
      Zone& zone = zones[z];
      for (const auto& h : zone.index[k]->nearest(sub)) zone.dist[k].push_back(h.distance);
      zone.measured[k].insert(zone.measured[k].end(), sub.begin(), sub.end());
      if (k == kRoof)
        for (const auto& h : zone.index[k]->vertical(sub)) zone.vertical.push_back(h.distance);
      if (k == kWall) {
        zone.own_roof.assign(sub.size(), kNaN);
        zone.other_roof.assign(sub.size(), kNaN);
        if (zone.index[kRoof]) {
          const auto hits = zone.index[kRoof]->vertical(sub);
          for (size_t i = 0; i < sub.size(); ++i) zone.own_roof[i] = hits[i].distance;
        }
        if (all_roofs) {  // counts only where the zone's own roof is not over the point, so it is another's
          const auto hits = all_roofs->vertical(sub);
          for (size_t i = 0; i < sub.size(); ++i)
            if (hits[i].owner != int(z)) zone.other_roof[i] = hits[i].distance;
        }
      }
    }
    outside += std::count(counted.begin(), counted.end(), 0);
  }

  // Report.
  std::printf("%-22s %8s %7s %7s %7s %7s %8s  %8s %7s %7s %7s %7s\n", "parcel", "roof n", "mean", "std",
              "rmse", "max", "vert rms", "wall n", "mean", "std", "rmse", "max");
  std::vector<Deviation> all[2], all_v;
  std::vector<std::vector<Deviation>> roof_parts, wall_parts;  // per zone
  nlohmann::json jz = nlohmann::json::array();
  long unmodelled[2] = {0, 0};
  for (const auto& z : zones) {
    const Deviation r = deviation(z.dist[kRoof]), w = deviation(z.dist[kWall]), v = deviation(z.vertical);
    const RoofCover cover = split_by_cover(z.dist[kRoof], z.vertical);
    const WallCover wall_cover = split_wall_cover(z.dist[kWall], z.own_roof, z.other_roof);
    roof_parts.push_back(cover.parts());
    wall_parts.push_back(wall_cover.parts());
    all[kRoof].push_back(r);
    all[kWall].push_back(w);
    all_v.push_back(v);
    unmodelled[kRoof] += z.unmodelled[kRoof];
    unmodelled[kWall] += z.unmodelled[kWall];
    if (clipper) print_row(z.id, r, v, w);
    jz.push_back({{"id", z.id}, {"roof", to_json(r)}, {"roof_vertical", to_json(v)},
                  {"roof_cover", to_json(kRoofPartKeys, cover.parts())}, {"wall", to_json(w)},
                  {"wall_cover", to_json(kWallPartKeys, wall_cover.parts())},
                  {"roof_faces", z.faces[kRoof].size()}, {"wall_faces", z.faces[kWall].size()},
                  {"unmodelled_roof_points", z.unmodelled[kRoof]}, {"unmodelled_wall_points", z.unmodelled[kWall]}});
  }
  const Deviation pr = pool(all[kRoof]), pw = pool(all[kWall]), pv = pool(all_v);
  const std::vector<Deviation> roof_cover = pool_parts(roof_parts), wall_cover = pool_parts(wall_parts);
  print_row("pooled", pr, pv, pw);
  print_parts("roof points by what the model has above or below them",
              {within_on_model("roof"), "a roof further off", "no roof"}, roof_cover);
  print_parts("wall points by where they stand",
              {within_on_model("wall"), "under the parcel's roof", "under another's roof", "under no roof"}, wall_cover);
  std::printf("roof points %zu, wall points %zu; in parcels without a model: %ld roof, %ld wall; "
              "outside every parcel: %ld; model faces outside every parcel: %ld\n",
              pts[kRoof].size(), pts[kWall].size(), unmodelled[0], unmodelled[1], outside, faces_outside);
  std::printf("distances in m: mean/std/rmse/max of |d|; vert rms = vertical distance RMSE\n");
  if (!o.residuals.empty()) write_residuals(o.residuals, zones);
  if (!o.json.empty()) {
    nlohmann::json j = {{"mesh", o.meshes}, {"cloud", o.cloud}, {"classes", o.classes}, {"buffer_m", o.buffer},
                        {"pooled", {{"roof", to_json(pr)}, {"roof_vertical", to_json(pv)}, {"roof_cover", to_json(kRoofPartKeys, roof_cover)},
                                    {"wall", to_json(pw)}, {"wall_cover", to_json(kWallPartKeys, wall_cover)}}},
                        {"points_outside_parcels", outside}, {"faces_outside_parcels", faces_outside}};
    if (clipper) j["parcels"] = jz;
    std::ofstream out(o.json);
    out << j.dump(2) << "\n";
    if (!out) throw InputError(o.json, "cannot write");
  }
}

}  // namespace

void register_evaluate(CLI::App& app) {
  auto o = std::make_shared<EvalOptions>();
  auto* cmd = app.add_subcommand(
      "evaluate", "Deviation of roof and wall points from a building model (per parcel and pooled)");
  cmd->add_option("--mesh", o->meshes, "models (.obj or .ply meshes, one or more: groups/materials "
                                       "named roof/wall are used, else faces are classed by their normal; "
                                       "or CityJSON .json: its semantic surfaces)")
      ->required()
      ->expected(1, -1);
  cmd->add_option("--cloud", o->cloud, "classified point cloud (LAS/PLY/PCD/XYZ)")->required();
  cmd->add_option("--classes", o->classes, "class codes, e.g. roof=6,wall=64 (unclassified files: all roof)")
      ->capture_default_str();
  cmd->add_option("--parcels", o->parcels, "parcel layer: per-parcel rows, measured as the batch does: "
                                           "roof points inside a parcel against its model's roofs, wall "
                                           "points within --buffer of it against its walls");
  cmd->add_option("--id-field", o->id_field,
                  "parcel id field (default: as the batch, NIB where the layer has it, else the feature id)");
  cmd->add_option("--buffer", o->buffer, "wall points this far outside a parcel still count for it, m")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--json", o->json, "also write the results as JSON");
  cmd->add_option("--residuals", o->residuals, "also write every measured point as CSV: parcel, kind (roof/wall), "
                                               "x, y, z, distance_m, vertical_m (roof points; empty: no roof above or below), "
                                               "part (of the split printed)");
  cmd->callback([o] {
    try {
      run_evaluate(*o);
    } catch (const std::exception& e) {
      std::cerr << "cadastre3d: error: " << e.what() << "\n";
      exit_code() = kExitError;
    }
  });
}

}  // namespace c3d::cli
