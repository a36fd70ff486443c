#include "core/mesh/mesh_files.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "core/mesh/glb.h"
#include "core/io/point_io.h"

namespace c3d {

namespace {

template <typename T>
void put(std::ofstream& out, T v) {
  out.write(reinterpret_cast<const char*>(&v), sizeof v);
}

// Seed 002's table: each of level 4's planar regions at this level.
nlohmann::json planar_json(const MeshLevel& l) {
  nlohmann::json regions = nlohmann::json::array();
  for (const RegionShape& r : l.planar)
    regions.push_back({{"region", r.region}, {"faces", r.faces}, {"length", r.length}, {"width", r.width},
                       {"thickness", r.thickness}});
  return regions;
}

nlohmann::json level_json(const MeshLevel& l) {
  const MeshMetrics& m = l.metrics;
  nlohmann::json j = {{"level", l.level},        {"faces", m.faces},
                      {"vertices", m.vertices},  {"seconds", l.seconds},
                      {"cloud_to_mesh", {{"mean", m.mean}, {"std", m.std}, {"p95", m.p95}, {"max", m.max}}},
                      {"mesh_to_cloud", m.mesh_to_cloud},
                      {"far_share", m.far_share}, {"closed", m.closed},
                      {"manifold", m.manifold},  {"volume", m.volume}};
  if (l.level >= 2) j["planar_regions"] = planar_json(l);
  if (l.level == 2 || l.level == 3)
    j["planar_change"] = {{"regions", l.change.regions}, {"lost", l.change.lost},
                          {"extent_change", l.change.extent_change}, {"thickness", l.change.thickness},
                          {"border_shift", {{"mean", l.border_shift.mean}, {"p95", l.border_shift.p95},
                                            {"max", l.border_shift.max}}}};
  return j;
}

}  // namespace

template <typename T>
T take(std::ifstream& in) {
  T v{};
  in.read(reinterpret_cast<char*>(&v), sizeof v);  // little-endian, as written
  return v;
}

TriMesh read_local_ply(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open");
  Vec3 offset = Vec3::Zero();
  size_t vertices = 0, faces = 0;
  std::string line;
  while (std::getline(in, line) && line != "end_header") {
    std::sscanf(line.c_str(), "comment world = local + (%lf, %lf, %lf)", &offset.x(), &offset.y(), &offset.z());
    std::sscanf(line.c_str(), "element vertex %zu", &vertices);
    std::sscanf(line.c_str(), "element face %zu", &faces);
  }
  TriMesh mesh;
  for (size_t i = 0; i < vertices && in; ++i) {
    const float x = take<float>(in), y = take<float>(in), z = take<float>(in);
    mesh.vertices.push_back(Vec3(x, y, z) + offset);
  }
  for (size_t i = 0; i < faces && in; ++i) {
    if (take<uint8_t>(in) != 3) throw InputError(path, "a face that is not a triangle: not a Cadastre3D mesh PLY");
    std::array<int, 3> t{};
    for (int& k : t) k = take<int32_t>(in);
    for (int k : t)
      if (k < 0 || size_t(k) >= vertices) throw InputError(path, "a face names a vertex it does not have");
    mesh.triangles.push_back(t);
  }
  if (!in) throw InputError(path, "cut short");
  return mesh;
}

void write_local_ply(const std::string& path, const TriMesh& mesh, const Vec3& offset) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw InputError(path, "cannot be written");
  char world[160];
  std::snprintf(world, sizeof world, "comment world = local + (%.3f, %.3f, %.3f)\n", offset.x(), offset.y(), offset.z());
  out << "ply\nformat binary_little_endian 1.0\n" << world << "element vertex " << mesh.vertices.size()
      << "\nproperty float x\nproperty float y\nproperty float z\nelement face " << mesh.triangles.size()
      << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const Vec3& v : mesh.vertices) put(out, float(v.x())), put(out, float(v.y())), put(out, float(v.z()));
  for (const auto& t : mesh.triangles) {
    put(out, uint8_t(3));
    for (int i : t) put(out, int32_t(i));
  }
  if (!out) throw InputError(path, "could not be written in full");
}

nlohmann::json ladder_json(const MeshLadder& ladder) {
  const PointSpacing& s = ladder.spacing;
  nlohmann::json levels = nlohmann::json::array();
  for (const MeshLevel& l : ladder.levels) levels.push_back(level_json(l));
  return {{"method", dense_method_name(ladder.method)},
          {"simplifier", simplifier_name(ladder.simplifier)},
          {"points", s.points},
          {"spacing", {{"min", s.min}, {"mean", s.mean}, {"median", s.median}, {"p95", s.p95}, {"max", s.max}, {"noise", s.noise}}},
          {"trimmed_faces", ladder.trimmed},
          {"hull", {{"alpha", ladder.hull_alpha}, {"offset", ladder.hull_offset}}},
          {"regions", {{"planar", ladder.regions.count(RegionKind::Planar)},
                       {"curved", ladder.regions.count(RegionKind::Curved)},
                       {"detail", ladder.regions.count(RegionKind::Detail)}}},
          {"levels", levels}};
}

std::string level_file_stem(const std::string& name, int level) { return name + "_level" + std::to_string(level); }

std::vector<std::string> write_ladder(const MeshLadder& ladder, const Vec3& offset, const std::string& dir,
                                      const std::string& name) {
  std::vector<std::string> paths;
  for (const MeshLevel& l : ladder.levels) {
    const std::string stem = dir + "/" + level_file_stem(name, l.level);
    paths.push_back(stem + ".ply");
    write_local_ply(paths.back(), l.mesh, offset);
    if (l.mesh.triangles.empty()) continue;  // glTF has no empty accessor
    paths.push_back(stem + ".glb");
    write_glb(paths.back(), l.mesh, offset, name + " level " + std::to_string(l.level));
  }
  paths.push_back(dir + "/" + name + "_ladder.json");
  std::ofstream json(paths.back());
  json << ladder_json(ladder).dump(2) << "\n";
  if (!json) throw InputError(paths.back(), "cannot be written");
  return paths;
}

MeshRun mesh_point_files(const std::vector<std::string>& clouds, DenseMethod method, const std::string& dir,
                         const std::string& name, Simplifier simplifier) {
  std::vector<Vec3> points;
  for (const std::string& path : clouds) {
    const PointCloud c = read_point_cloud(path);
    points.insert(points.end(), c.points.begin(), c.points.end());
  }
  std::string named = clouds.empty() ? "mesh: no --cloud" : clouds.front();
  if (clouds.size() > 1) named += " (and " + std::to_string(clouds.size() - 1) + " more)";
  if (points.size() < 4)
    throw InputError(named, std::to_string(points.size()) + " points: a mesh needs 4 at least");
  const Vec3 spread = point_spread(points);
  if (spread.y() <= 1e-6 * spread.x()) throw InputError(named, "the points lie on a line or at one place: there is no surface to mesh");
  MeshRun run;
  {
    Vec3 lo = points.front();
    for (const Vec3& p : points) lo = lo.cwiseMin(p);
    run.offset = Vec3(std::floor(lo.x()), std::floor(lo.y()), std::floor(lo.z()));
    for (Vec3& p : points) p -= run.offset;
  }
  run.ladder = mesh_ladder(points, method, {}, simplifier);
  std::filesystem::create_directories(dir);
  run.files = write_ladder(run.ladder, run.offset, dir, name);
  return run;
}

std::string ladder_text(const MeshLadder& ladder) {
  char line[200];
  std::snprintf(line, sizeof line, "%zu points, spacing mean %.3f m (p95 %.3f m), dense method %s\n",
                ladder.spacing.points, ladder.spacing.mean, ladder.spacing.p95, dense_method_name(ladder.method));
  std::string out = line;
  std::snprintf(line, sizeof line, "regions of level 4: %zu planar, %zu curved, %zu detail; simplified by %s\n",
                ladder.regions.count(RegionKind::Planar), ladder.regions.count(RegionKind::Curved),
                ladder.regions.count(RegionKind::Detail), simplifier_name(ladder.simplifier));
  out += line;
  out += "level    faces  cloud-to-mesh mean / p95 / max (m)  mesh-to-cloud (m)  closed  seconds  planar extent change (m)\n";
  for (auto it = ladder.levels.rbegin(); it != ladder.levels.rend(); ++it) {
    const MeshMetrics& m = it->metrics;
    std::snprintf(line, sizeof line, "%5d %8zu  %8.4f / %8.4f / %8.4f        %10.3f  %6s  %7.2f", it->level, m.faces,
                  m.mean, m.p95, m.max, m.mesh_to_cloud, m.closed ? "yes" : "no", it->seconds);
    out += line;
    if (it->level == 2 || it->level == 3) {
      std::snprintf(line, sizeof line, "  %.4f (%zu of %zu regions lost)", it->change.extent_change, it->change.lost,
                    it->change.regions);
      out += line;
    }
    out += "\n";
  }
  return out;
}

}  // namespace c3d
