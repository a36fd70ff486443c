#include "cadastre/store/gpkg_rtree.h"

#include <sqlite3.h>

#include <cmath>

#include "cadastre/store/gpkg_geometry.h"

namespace c3d::gpkg_rtree {

namespace {

// The xy box of a geometry blob; false for NULL, empty or unreadable.
bool box_of(sqlite3_value* v, double env[4]) {
  if (sqlite3_value_type(v) != SQLITE_BLOB) return false;
  const auto* data = static_cast<const std::uint8_t*>(sqlite3_value_blob(v));
  const std::size_t n = std::size_t(sqlite3_value_bytes(v));
  if (gpkg_envelope_xy(data, n, env)) return std::isfinite(env[0]);
  try {  // no envelope in the header: from the coordinates
    env[0] = env[1] = HUGE_VAL;
    env[2] = env[3] = -HUGE_VAL;
    for (const Face& f : gpkg_read_faces(data, n, Vec3::Zero()))
      for (const Vec3& p : f.ring) {
        env[0] = std::min(env[0], p.x()), env[1] = std::min(env[1], p.y());
        env[2] = std::max(env[2], p.x()), env[3] = std::max(env[3], p.y());
      }
  } catch (const std::exception&) {
    return false;
  }
  return std::isfinite(env[0]);
}

template <int k>
void st_bound(sqlite3_context* ctx, int, sqlite3_value** argv) {
  double env[4];  // min_x, min_y, max_x, max_y
  if (box_of(argv[0], env)) sqlite3_result_double(ctx, env[k]);
  else sqlite3_result_null(ctx);
}

void st_is_empty(sqlite3_context* ctx, int, sqlite3_value** argv) {
  double env[4];
  sqlite3_result_int(ctx, box_of(argv[0], env) ? 0 : 1);
}

// The triggers as GDAL 3.6 writes them (GeoPackage 1.3, Annex F.3).
std::string triggers(const std::string& t, const std::string& r) {
  const std::string values = " VALUES (NEW.\"fid\",ST_MinX(NEW.\"geom\"), ST_MaxX(NEW.\"geom\"),"
                             "ST_MinY(NEW.\"geom\"), ST_MaxY(NEW.\"geom\")); END;";
  const std::string on = " ON \"" + t + "\" ";
  const std::string tr = "CREATE TRIGGER IF NOT EXISTS \"" + r;
  return tr + "_insert\" AFTER INSERT" + on + "WHEN (new.\"geom\" NOT NULL AND NOT ST_IsEmpty(NEW.\"geom\")) "
         "BEGIN INSERT OR REPLACE INTO \"" + r + "\"" + values +
         tr + "_update1\" AFTER UPDATE OF \"geom\"" + on + "WHEN OLD.\"fid\" = NEW.\"fid\" AND "
         "(NEW.\"geom\" NOTNULL AND NOT ST_IsEmpty(NEW.\"geom\")) BEGIN INSERT OR REPLACE INTO \"" + r + "\"" +
         values +
         tr + "_update2\" AFTER UPDATE OF \"geom\"" + on + "WHEN OLD.\"fid\" = NEW.\"fid\" AND "
         "(NEW.\"geom\" ISNULL OR ST_IsEmpty(NEW.\"geom\")) BEGIN DELETE FROM \"" + r +
         "\" WHERE id = OLD.\"fid\"; END;" +
         tr + "_update3\" AFTER UPDATE" + on + "WHEN OLD.\"fid\" != NEW.\"fid\" AND "
         "(NEW.\"geom\" NOTNULL AND NOT ST_IsEmpty(NEW.\"geom\")) BEGIN DELETE FROM \"" + r +
         "\" WHERE id = OLD.\"fid\"; INSERT OR REPLACE INTO \"" + r + "\"" + values +
         tr + "_update4\" AFTER UPDATE" + on + "WHEN OLD.\"fid\" != NEW.\"fid\" AND "
         "(NEW.\"geom\" ISNULL OR ST_IsEmpty(NEW.\"geom\")) BEGIN DELETE FROM \"" + r +
         "\" WHERE id IN (OLD.\"fid\", NEW.\"fid\"); END;" +
         tr + "_delete\" AFTER DELETE" + on + "WHEN old.\"geom\" NOT NULL BEGIN DELETE FROM \"" + r +
         "\" WHERE id = OLD.\"fid\"; END;";
}

}  // namespace

void register_functions(sql::Db& db) {
  const int flags = SQLITE_UTF8 | SQLITE_DETERMINISTIC;
  sqlite3* h = db.get();
  sqlite3_create_function(h, "ST_MinX", 1, flags, nullptr, st_bound<0>, nullptr, nullptr);
  sqlite3_create_function(h, "ST_MinY", 1, flags, nullptr, st_bound<1>, nullptr, nullptr);
  sqlite3_create_function(h, "ST_MaxX", 1, flags, nullptr, st_bound<2>, nullptr, nullptr);
  sqlite3_create_function(h, "ST_MaxY", 1, flags, nullptr, st_bound<3>, nullptr, nullptr);
  sqlite3_create_function(h, "ST_IsEmpty", 1, flags, nullptr, st_is_empty, nullptr, nullptr);
}

void create(sql::Db& db, const std::string& table) {
  const std::string r = "rtree_" + table + "_geom";
  bool exists = false;
  {
    sql::Stmt q(db, "SELECT 1 FROM sqlite_master WHERE name=?");
    q.bind(r);
    exists = q.step();
  }
  if (!exists) {
    db.exec("CREATE VIRTUAL TABLE \"" + r + "\" USING rtree(id, minx, maxx, miny, maxy);"
            "INSERT OR REPLACE INTO \"" + r + "\" SELECT fid, ST_MinX(geom), ST_MaxX(geom), ST_MinY(geom), "
            "ST_MaxY(geom) FROM \"" + table + "\" WHERE geom NOT NULL AND NOT ST_IsEmpty(geom);");
  }
  db.exec(triggers(table, r));
  sql::Stmt ext(db,
                "INSERT OR IGNORE INTO gpkg_extensions (table_name, column_name, extension_name, "
                "definition, scope) VALUES (?, 'geom', 'gpkg_rtree_index', "
                "'http://www.geopackage.org/spec120/#extension_rtree', 'write-only')");
  ext.bind(table).run();
}

}  // namespace c3d::gpkg_rtree
