#include "cadastre/batch/building_meshes.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <unordered_map>

#include "cadastre/report/report.h"
#include "cadastre/store/gis.h"
#include "core/cpu_clock.h"
#include "core/error.h"
#include "core/geometry/geometry.h"
#include "core/geometry/polygon_ops.h"
#include "core/io/file_names.h"
#include "core/io/sha256.h"
#include "core/mesh/ladder.h"
#include "core/mesh/mesh_files.h"

namespace fs = std::filesystem;

namespace c3d {

namespace {

Vec2 plan(const Vec3& p) { return p.head<2>(); }

// What the building covers seen from above: its roof (overhangs included) and its footprint.
MultiPolygon2 covered_plan(const Building& b) {
  std::vector<Face> faces;
  for (const Element& e : b.elements)
    if (e.type == ElementType::Roof || e.type == ElementType::Ground) faces.insert(faces.end(), e.faces.begin(), e.faces.end());
  return store_gis::plan_of(faces.empty() ? b.solid : faces, Vec3::Zero());
}

// How high a building's own points may lie over a plan point: its roof
// there (the highest roof face over it), else its highest roof corner.
class RoofCeiling {
 public:
  explicit RoofCeiling(const Building& b) {
    for (const Element& e : b.elements)
      if (e.type == ElementType::Roof)
        for (const Face& f : e.faces) {
          faces_.push_back(&f);
          for (const Vec3& v : f.ring) top_ = std::max(top_, v.z());
        }
  }
  double over(const Vec2& q) const {
    double z = -HUGE_VAL;
    for (const Face* f : faces_)
      if (in_ring_plan(f->ring, q)) z = std::max(z, height_on(*f, q));
    return z > -HUGE_VAL ? z : top_;
  }

  static double height_on(const Face& f, const Vec2& q) {
    const Vec3 n = unit_normal(f);
    if (std::abs(n.z()) < 1e-9) return f.ring.front().z();
    const Vec3& a = f.ring.front();
    return a.z() - (n.x() * (q.x() - a.x()) + n.y() * (q.y() - a.y())) / n.z();
  }

 private:
  std::vector<const Face*> faces_;
  double top_ = -HUGE_VAL;
};

// The points near the building in plan (`near`), between its terrain and
// `lift` over its roof: above it stands another surface, a taller
// neighbour's wall or eave (a model lower than its own points shows in its
// roof RMSE instead).
template <class Near>
void add_points_near(const std::vector<Vec3>& points, const Building& b, const RoofCeiling& roof, double lift,
                     const Near& near, std::vector<Vec3>& out) {
  for (const Vec3& q : points)
    if (q.z() >= b.terrain_z && near(plan(q)) && q.z() <= roof.over(plan(q)) + lift) out.push_back(q);
}

// Each cell's highest point, cells `cell` wide in plan.
class TopGrid {
 public:
  TopGrid(const std::vector<Vec3>& points, double cell) : cell_(cell) {
    for (const Vec3& p : points) {
      auto [it, fresh] = top_.try_emplace(key(p.x(), p.y()), p.z());
      if (!fresh) it->second = std::max(it->second, p.z());
    }
  }
  // The highest point in the 3 x 3 cells around q; NaN where there is none.
  double around(const Vec2& q) const {
    double top = kNaN;
    const long i = long(std::floor(q.x() / cell_)), j = long(std::floor(q.y() / cell_));
    for (long di = -1; di <= 1; ++di)
      for (long dj = -1; dj <= 1; ++dj) {
        auto it = top_.find(pack(i + di, j + dj));
        if (it != top_.end() && !(it->second <= top)) top = it->second;
      }
    return top;
  }

 private:
  static long long pack(long i, long j) { return (static_cast<long long>(i) << 32) ^ (j & 0xffffffffLL); }
  long long key(double x, double y) const { return pack(long(std::floor(x / cell_)), long(std::floor(y / cell_))); }
  double cell_;
  std::unordered_map<long long, double> top_;
};

std::vector<Vec2> ring_samples(const Ring2& ring, double step) {
  std::vector<Vec2> out;
  for (size_t i = 0; i < ring.size(); ++i) {
    const Vec2 a = ring[i], b = ring[(i + 1) % ring.size()];
    const int n = std::max(1, int(std::ceil((b - a).norm() / step)));
    for (int k = 0; k < n; ++k) out.push_back(a + (b - a) * (double(k) / n));
  }
  return out;
}

std::string file_sha(const std::string& out_dir, const std::string& rel) {
  return rel.empty() ? std::string() : sha256_file((fs::path(out_dir) / rel).string());
}

MeshLevelRecord level_record(const MeshLevel& l, const std::string& rel_stem) {
  const MeshMetrics& m = l.metrics;
  MeshLevelRecord r;
  r.level = l.level;
  r.faces = long(m.faces);
  r.vertices = long(m.vertices);
  r.seconds = l.seconds;
  r.mean_m = m.mean, r.std_m = m.std, r.p95_m = m.p95, r.max_m = m.max;
  r.mesh_to_cloud_m = m.mesh_to_cloud;
  r.far_share = m.far_share;
  r.closed = m.closed, r.manifold = m.manifold;
  if (m.closed) r.volume = m.volume, r.roof_area = upward_area(l.mesh);
  if (l.level >= 2) {
    r.planar_regions = long(std::count_if(l.planar.begin(), l.planar.end(), [](const RegionShape& s) { return s.faces > 0; }));
    r.thickness_m = 0;
    for (const RegionShape& s : l.planar) r.thickness_m = std::max(r.thickness_m, s.thickness);
  }
  if (l.level == 2 || l.level == 3) r.planar_lost = long(l.change.lost), r.extent_change_m = l.change.extent_change;
  const std::string level_stem = level_file_stem(rel_stem, l.level);
  r.ply = level_stem + ".ply";
  if (m.faces > 0) r.glb = level_stem + ".glb", r.picture = level_stem + ".svg";
  return r;
}

void write_picture(const TriMesh& mesh, const std::string& title, const std::string& path) {
  std::ofstream out(path);
  out << mesh_svg(mesh, title);
  if (!out) throw InputError(path, "cannot be written");
}

std::string percent(double share) {
  char text[32];
  std::snprintf(text, sizeof text, "%+.0f %%", 100 * share);
  return text;
}

// A ring's plan area (unsigned) and its first moments (area x centroid).
struct PlanMoments {
  double area = 0;
  Vec2 moment = Vec2::Zero();
};
PlanMoments plan_moments(const Ring3& ring) {
  double a2 = 0;  // twice the signed area
  Vec2 m6 = Vec2::Zero();  // six times the signed first moments
  for (size_t i = 0; i < ring.size(); ++i) {
    const Vec2 p = plan(ring[i]), q = plan(ring[(i + 1) % ring.size()]);
    const double cross = p.x() * q.y() - q.x() * p.y();
    a2 += cross;
    m6 += cross * (p + q);
  }
  const double sign = a2 < 0 ? -1.0 : 1.0;
  return {sign * a2 / 2, sign * m6 / 6};
}

// The volume under the model's roof, overhangs included, down to its
// terrain: what the hull of its points, closed under the roof's outline,
// holds. Over a plane, plan area x height at the plan's centroid is exact.
double volume_under_roof(const Building& b) {
  double v = 0;
  for (const Element& e : b.elements)
    if (e.type == ElementType::Roof)
      for (const Face& f : e.faces) {
        PlanMoments m = plan_moments(f.ring);
        for (const Ring3& h : f.holes) {
          const PlanMoments hole = plan_moments(h);
          m.area -= hole.area;
          m.moment -= hole.moment;
        }
        if (m.area > 0) v += m.area * (RoofCeiling::height_on(f, m.moment / m.area) - b.terrain_z);
      }
  return v;
}

// The element model against the closed hull of its points (kMeshVolumeBound, kMeshRoofAreaBound).
void check_against_hull(const Building& b, BuildingMesh& m) {
  const MeshLevelRecord& hull = m.levels.front();
  if (!hull.closed) {
    m.problem = "level 1 is not closed: the model is not checked against it";
    return;
  }
  const double roof = totals(b).roof;
  m.model_volume = volume_under_roof(b);
  m.volume_diff = m.model_volume > 0 ? (hull.volume - m.model_volume) / m.model_volume : kNaN;
  m.roof_area_diff = roof > 0 ? (hull.roof_area - roof) / roof : kNaN;
  char text[160];
  if (std::abs(m.volume_diff) > kMeshVolumeBound) {
    std::snprintf(text, sizeof text, "volume under the roof %.0f m3 against the hull's %.0f m3 (%s)", m.model_volume, hull.volume,
                  percent(m.volume_diff).c_str());
    m.flag = text;
  }
  if (std::abs(m.roof_area_diff) > kMeshRoofAreaBound) {
    std::snprintf(text, sizeof text, "roof area %.0f m2 against the hull's %.0f m2 (%s)", roof, hull.roof_area,
                  percent(m.roof_area_diff).c_str());
    m.flag += (m.flag.empty() ? "" : "; ") + std::string(text);
  }
}

void mesh_building(const ParcelScene& scene, const LocalFrame& frame, const MeshOutput& out, Building& b) {
  BuildingMesh& m = b.mesh;
  m = BuildingMesh{};
  m.method = dense_method_name(out.method);
  const std::vector<Vec3> points = building_points(scene, b);
  m.points = long(points.size());
  if (points.size() < 4) {
    m.problem = std::to_string(points.size()) + " points of its own: a mesh needs 4 at least";
    return;
  }
  const Vec3 spread = point_spread(points);
  if (spread.y() <= 1e-6 * spread.x()) {
    m.problem = "its points lie on a line: there is no surface to mesh";
    return;
  }
  const MeshLadder ladder = mesh_ladder(
      points, out.method, [&](double spacing) { return hull_closure(b, points, spacing); }, out.simplifier);
  m.spacing_m = ladder.spacing.mean;
  m.hull_alpha_m = ladder.hull_alpha;
  const std::string stem = file_stem_for_id(b.id);
  const fs::path dir = fs::path(out.out_dir) / kMeshFolder;
  write_ladder(ladder, frame.origin, dir.string(), stem);
  for (const MeshLevel& l : ladder.levels) {
    MeshLevelRecord r = level_record(l, std::string(kMeshFolder) + "/" + stem);
    if (!r.picture.empty())
      write_picture(l.mesh, b.id + " level " + std::to_string(l.level), (fs::path(out.out_dir) / r.picture).string());
    r.ply_sha256 = file_sha(out.out_dir, r.ply);
    r.glb_sha256 = file_sha(out.out_dir, r.glb);
    r.picture_sha256 = file_sha(out.out_dir, r.picture);
    m.levels.push_back(std::move(r));
  }
  check_against_hull(b, m);
}

}  // namespace

std::vector<Vec3> building_points(const ParcelScene& scene, const Building& b) {
  const MultiPolygon2 shape = covered_plan(b);
  const RoofCeiling roof(b);
  // Roof points scatter about the roof by its fit's RMSE.
  const double rmse = std::isfinite(b.attributes.roof_rmse) ? b.attributes.roof_rmse : b.roof_deviation.rmse;
  const double noise = 3 * (std::isfinite(rmse) ? rmse : 0.0);
  auto gather = [&](double reach, const auto& near) {
    std::vector<Vec3> out;
    add_points_near(scene.roof_points, b, roof, noise + reach, near, out);
    add_points_near(scene.wall_points, b, roof, noise + reach, near, out);
    return out;
  };
  const std::vector<Vec3> inside = gather(0.0, [&](const Vec2& q) { return poly::covers(shape, q); });
  if (inside.size() < 2) return inside;
  // An edge of the model lies within about a spacing of the points that made it.
  const double reach = point_spacing(inside).mean;
  return gather(reach, [&](const Vec2& q) { return poly::distance(shape, q) <= reach; });
}

std::vector<Vec3> hull_closure(const Building& b, const std::vector<Vec3>& points, double step) {
  std::vector<Vec3> out;
  if (!(step > 0)) return out;
  const MultiPolygon2 foot = covered_plan(b);
  const double z0 = b.terrain_z;
  Vec2 lo(HUGE_VAL, HUGE_VAL), hi(-HUGE_VAL, -HUGE_VAL);
  for (const Polygon2& p : foot)
    for (const Vec2& q : p.outer) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
  for (double x = lo.x() + step / 2; x < hi.x(); x += step)
    for (double y = lo.y() + step / 2; y < hi.y(); y += step)
      if (poly::covers(foot, Vec2(x, y))) out.emplace_back(x, y, z0);
  const TopGrid tops(points, step);  // the roof within 1.5 spacings: its eave, not its ridge
  for (const Polygon2& p : foot) {
    std::vector<Vec2> edge = ring_samples(p.outer, step);
    for (const Ring2& h : p.holes) {
      const std::vector<Vec2> more = ring_samples(h, step);
      edge.insert(edge.end(), more.begin(), more.end());
    }
    for (const Vec2& q : edge) {
      const double top = tops.around(q);
      const double rise = std::isnan(top) ? 0.0 : top - z0;
      const int n = std::max(0, int(std::floor(rise / step)));
      for (int k = 0; k <= n; ++k) out.emplace_back(q.x(), q.y(), z0 + rise * (n ? double(k) / n : 0.0));
    }
  }
  return out;
}

void mesh_buildings(const ParcelScene& scene, const LocalFrame& frame, const MeshOutput& out, ParcelResult& r) {
  if (r.buildings.empty()) return;
  const double start = thread_cpu_seconds();
  const fs::path dir = fs::path(out.out_dir) / kMeshFolder;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw InputError(dir.string(), "cannot be created: " + ec.message());
  for (Building& b : r.buildings) try {
      mesh_building(scene, frame, out, b);
    } catch (const InputError&) {
      throw;  // a file that cannot be written: the batch stops, as for the store
    } catch (const std::exception& e) {
      b.mesh.levels.clear();
      b.mesh.problem = std::string("the mesh could not be made: ") + e.what();
    }
  r.timings.push_back({"mesh", thread_cpu_seconds() - start});
}

void gather_mesh_files(const std::vector<std::string>& shard_stores, const std::string& out_dir) {
  const fs::path to = fs::path(out_dir) / kMeshFolder;
  for (const std::string& store : shard_stores) {
    const fs::path from = fs::path(store).parent_path() / kMeshFolder;
    std::error_code ec;
    if (!fs::is_directory(from, ec) || fs::equivalent(from, to, ec)) continue;
    fs::create_directories(to, ec);
    for (const auto& f : fs::directory_iterator(from)) {
      const fs::path target = to / f.path().filename();
      fs::remove(target, ec);
      fs::create_hard_link(f.path(), target, ec);
      if (ec) fs::copy_file(f.path(), target, ec);
      if (ec) throw InputError(target.string(), "cannot be written: " + ec.message());
    }
  }
}

}  // namespace c3d
