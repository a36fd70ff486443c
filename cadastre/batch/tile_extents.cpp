#include "cadastre/batch/tile_extents.h"

#include <cstdio>
#include <filesystem>

#include "cadastre/store/sql_db.h"
#include "core/error.h"
#include "core/io/sha256.h"
#include "core/log.h"

namespace c3d {

namespace {

constexpr double kHeaderSlackM = 1e-3;  // writers round bounds to the coordinate scale

std::string exact_text(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string metres_text(double v) {  // a coordinate to the centimetre, as the LAS reader's messages
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.2f", v);
  return buf;
}

// A row's own checksum: a damaged index row is decoded again, never trusted.
std::string row_check(const std::string& sha, const CloudExtent& e) {
  return sha256_hex(sha + "|" + exact_text(e.min_x) + "|" + exact_text(e.min_y) + "|" + exact_text(e.max_x) + "|" +
                    exact_text(e.max_y) + "|" + std::to_string(e.points));
}

sql::Db open_index(const std::string& path) {
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  sql::Db db(path, false);
  db.exec("CREATE TABLE IF NOT EXISTS tile_extent (sha256 TEXT PRIMARY KEY, min_x REAL, min_y REAL, "
          "max_x REAL, max_y REAL, points INTEGER, row_check TEXT)");
  return db;
}

bool look_up(const std::string& db_path, const std::string& sha, CloudExtent& e) {
  sql::Db db = open_index(db_path);
  sql::Stmt q(db, "SELECT min_x, min_y, max_x, max_y, points, row_check FROM tile_extent WHERE sha256 = ?");
  q.bind(sha);
  if (!q.step()) return false;
  CloudExtent found = e;
  found.min_x = q.get_double(0), found.min_y = q.get_double(1);
  found.max_x = q.get_double(2), found.max_y = q.get_double(3);
  found.points = uint64_t(q.get_int(4));
  if (q.get_text(5) != row_check(sha, found)) return false;
  e = found;
  return true;
}

void record(const std::string& db_path, const std::string& sha, const CloudExtent& e) {
  sql::Db db = open_index(db_path);
  sql::Stmt put(db, "INSERT OR REPLACE INTO tile_extent VALUES (?, ?, ?, ?, ?, ?, ?)");
  put.bind(sha).bind(e.min_x).bind(e.min_y).bind(e.max_x).bind(e.max_y).bind(static_cast<long long>(e.points));
  put.bind(row_check(sha, e));
  put.run();
}

}  // namespace

std::string tile_index_path(const char* xdg_cache_home, const char* home) {
  if (xdg_cache_home && *xdg_cache_home == '/') return std::string(xdg_cache_home) + "/cadastre3d/tile-extents.sqlite";
  if (home && *home) return std::string(home) + "/.cache/cadastre3d/tile-extents.sqlite";
  return "";
}

TileExtentIndex::TileExtentIndex(std::string db_path) : db_path_(std::move(db_path)) {}

CloudExtent TileExtentIndex::decoded(const std::string& path, const std::string& sha256, const CloudExtent& header) {
  CloudExtent e = header;
  e.from_header = false;
  if (!db_path_.empty()) try {
      if (look_up(db_path_, sha256, e)) return e;
    } catch (const std::exception& x) {
      log::debug("tile index " + db_path_ + " not read: " + x.what());
    }
  e = decoded_cloud_extent(path);
  e.crs_wkt = header.crs_wkt;
  if (!db_path_.empty()) try {
      record(db_path_, sha256, e);
    } catch (const std::exception& x) {
      log::debug("tile index " + db_path_ + " not written: " + x.what());
    }
  return e;
}

std::string header_short_note(const CloudExtent& header, const CloudExtent& decoded) {
  const bool inside = decoded.min_x >= header.min_x - kHeaderSlackM && decoded.max_x <= header.max_x + kHeaderSlackM &&
                      decoded.min_y >= header.min_y - kHeaderSlackM && decoded.max_y <= header.max_y + kHeaderSlackM;
  if (inside || decoded.points == 0) return "";
  return "the points reach x " + metres_text(decoded.min_x) + " to " + metres_text(decoded.max_x) + ", y " +
         metres_text(decoded.min_y) + " to " + metres_text(decoded.max_y) + ", beyond the header's bounds (x " +
         metres_text(header.min_x) + " to " + metres_text(header.max_x) + ", y " +
         metres_text(header.min_y) + " to " + metres_text(header.max_y) + "): tile indexed by its decoded extent";
}

}  // namespace c3d
