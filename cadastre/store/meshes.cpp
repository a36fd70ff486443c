#include "cadastre/store/meshes.h"

#include "cadastre/store/columns.h"
#include "cadastre/store/schema.h"
#include "core/geometry/geometry.h"

namespace c3d::store_meshes {

Writer::Writer(const sql::Db& db)
    : mesh_(db, store_columns::insert_sql(store_columns::kBuildingMesh)),
      level_(db, store_columns::insert_sql(store_columns::kBuildingMeshLevel)) {}

void Writer::write(std::int64_t building_fid, const Building& b) {
  const BuildingMesh& m = b.mesh;
  if (m.method.empty()) return;
  const long long fid = building_fid;
  const double hull_volume = m.levels.empty() ? kNaN : m.levels.front().volume;
  const double hull_roof = m.levels.empty() ? kNaN : m.levels.front().roof_area;
  mesh_.bind(fid).bind(b.id).bind(m.method).bind(m.points).bind(m.spacing_m).bind(m.model_volume).bind(hull_volume)
      .bind(m.volume_diff).bind(totals(b).roof).bind(hull_roof).bind(m.roof_area_diff).bind(m.flag).bind(m.problem)
      .run();
  for (const MeshLevelRecord& l : m.levels)
    level_.bind(fid).bind(l.level).bind(l.faces).bind(l.vertices).bind(l.seconds).bind(l.mean_m).bind(l.std_m)
        .bind(l.p95_m).bind(l.max_m).bind(l.mesh_to_cloud_m).bind(l.far_share).bind(l.closed ? 1 : 0)
        .bind(l.manifold ? 1 : 0).bind(l.volume).bind(l.roof_area).bind(l.planar_regions).bind(l.planar_lost).bind(l.extent_change_m)
        .bind(l.thickness_m).bind(l.ply).bind(l.ply_sha256).bind(l.glb)
        .bind(l.glb_sha256).bind(l.picture).bind(l.picture_sha256).run();
}

Reader::Reader(const sql::Db& db)
    : has_tables_(store_schema::has_column(db, "building_mesh", "flag") &&
                  store_schema::has_column(db, "building_mesh_level", "picture_sha256")) {
  using namespace store_columns;
  if (!has_tables_) return;
  mesh_ = sql::Stmt(db, "SELECT " + select_list(db, kBuildingMesh) + " FROM building_mesh WHERE building_fid=?");
  level_ = sql::Stmt(db, "SELECT " + select_list(db, kBuildingMeshLevel) +
                             " FROM building_mesh_level WHERE building_fid=? ORDER BY level");
}

void Reader::read(std::int64_t building_fid, Building& b) {
  if (!has_tables_) return;
  BuildingMesh& m = b.mesh;
  mesh_.bind(static_cast<long long>(building_fid));
  if (mesh_.step()) {
    m.method = mesh_.get_text("method");
    m.points = long(mesh_.get_int("points"));
    m.spacing_m = mesh_.get_double("spacing");
    m.model_volume = mesh_.get_double("model_volume");
    m.volume_diff = mesh_.get_double("volume_diff");
    m.roof_area_diff = mesh_.get_double("roof_area_diff");
    m.flag = mesh_.get_text("flag");
    m.problem = mesh_.get_text("problem");
  }
  mesh_.reset();
  level_.bind(static_cast<long long>(building_fid));
  while (level_.step()) {
    MeshLevelRecord l;
    l.level = int(level_.get_int("level"));
    l.faces = long(level_.get_int("faces"));
    l.vertices = long(level_.get_int("vertices"));
    l.seconds = level_.get_double("seconds");
    l.mean_m = level_.get_double("c2m_mean");
    l.std_m = level_.get_double("c2m_std");
    l.p95_m = level_.get_double("c2m_p95");
    l.max_m = level_.get_double("c2m_max");
    l.mesh_to_cloud_m = level_.get_double("mesh_to_cloud");
    l.far_share = level_.get_double("far_share");
    l.closed = level_.get_int("closed") != 0;
    l.manifold = level_.get_int("manifold") != 0;
    l.volume = level_.get_double("volume");
    l.roof_area = level_.get_double("roof_area");
    l.planar_regions = long(level_.get_int("planar_regions"));
    l.planar_lost = long(level_.get_int("planar_lost"));
    l.extent_change_m = level_.get_double("extent_change");
    l.thickness_m = level_.get_double("thickness");
    l.ply = level_.get_text("ply");
    l.ply_sha256 = level_.get_text("ply_sha256");
    l.glb = level_.get_text("glb");
    l.glb_sha256 = level_.get_text("glb_sha256");
    l.picture = level_.get_text("picture");
    l.picture_sha256 = level_.get_text("picture_sha256");
    m.levels.push_back(std::move(l));
  }
  level_.reset();
}

}  // namespace c3d::store_meshes
