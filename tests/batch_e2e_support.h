#pragma once
// Shared by the end-to-end batch tests (batch_e2e_test.cpp,
// batch_resume_test.cpp): the CLI run as a user runs it, the store read with
// plain SQLite (independent of the store code under test), store snapshots to
// compare, and a batch as a child process that can be killed.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sqlite3.h>
#include <csignal>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "tests/test_support.h"

namespace e2e {

using namespace c3d;
namespace fs = std::filesystem;

// ---------------------------------------------------------------------------
// Plain SQLite reading (independent of the store code under test).

struct Cell {
  bool null = false, number = false;
  double d = 0;
  std::string s;
};
using Row = std::vector<Cell>;

class Sqlite {
 public:
  explicit Sqlite(const std::string& path) {
    if (sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) {
      error_ = db_ ? sqlite3_errmsg(db_) : "cannot open";
      sqlite3_close(db_);
      db_ = nullptr;
      return;
    }
    sqlite3_busy_timeout(db_, 5000);
  }
  ~Sqlite() { sqlite3_close(db_); }
  Sqlite(const Sqlite&) = delete;
  Sqlite& operator=(const Sqlite&) = delete;

  bool ok() const { return db_ != nullptr; }
  const std::string& error() const { return error_; }

  // Rows of a query; on error returns false and keeps the message in error().
  bool query(const std::string& sql, std::vector<Row>* rows) {
    rows->clear();
    if (!db_) return false;
    sqlite3_stmt* st = nullptr;
    if (sqlite3_prepare_v2(db_, sql.c_str(), -1, &st, nullptr) != SQLITE_OK) {
      error_ = sqlite3_errmsg(db_);
      return false;
    }
    int rc;
    while ((rc = sqlite3_step(st)) == SQLITE_ROW) {
      Row r;
      for (int c = 0; c < sqlite3_column_count(st); ++c) {
        Cell cell;
        int t = sqlite3_column_type(st, c);
        cell.null = t == SQLITE_NULL;
        cell.number = t == SQLITE_INTEGER || t == SQLITE_FLOAT;
        if (cell.number) cell.d = sqlite3_column_double(st, c);
        if (t == SQLITE_BLOB) {
          auto* b = static_cast<const unsigned char*>(sqlite3_column_blob(st, c));
          cell.s.assign(reinterpret_cast<const char*>(b), size_t(sqlite3_column_bytes(st, c)));
        } else if (!cell.null) {
          cell.s = reinterpret_cast<const char*>(sqlite3_column_text(st, c));
        }
        r.push_back(cell);
      }
      rows->push_back(std::move(r));
    }
    if (rc != SQLITE_DONE) error_ = sqlite3_errmsg(db_);
    sqlite3_finalize(st);
    return rc == SQLITE_DONE;
  }

  std::vector<Row> rows(const std::string& sql) {
    std::vector<Row> r;
    EXPECT_TRUE(query(sql, &r)) << sql << ": " << error_;
    return r;
  }
  double number(const std::string& sql) {
    auto r = rows(sql);
    return r.empty() || r[0].empty() || r[0][0].null ? std::nan("") : r[0][0].d;
  }
  std::string text(const std::string& sql) {
    auto r = rows(sql);
    return r.empty() || r[0].empty() ? std::string() : r[0][0].s;
  }

 private:
  sqlite3* db_ = nullptr;
  std::string error_;
};

inline std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// Sample town with fewer points than the default (faster batches, same layouts).
inline std::string make_town(const std::string& dir, int parcels, int seed, const std::string& extra = "") {
  std::string out;
  int rc = test::run_cli("sample --out " + dir + " --parcels " + std::to_string(parcels) +
                             " --seed " + std::to_string(seed) + " " + extra,
                         &out);
  EXPECT_EQ(rc, 0) << out;
  return out;
}

inline std::string batch_args(const std::string& town, const std::string& out) {
  return "batch --cloud " + town + "/cloud.las --parcels " + town + "/parcels.gpkg --dtm " + town +
         "/dtm.tif --out " + out;
}

// ---------------------------------------------------------------------------
// What a store holds, as comparable rows keyed by natural ids (no fids, run ids,
// timestamps). Blobs (geometries) are compared byte for byte.

using Snapshot = std::map<std::string, std::vector<Row>>;

inline const std::map<std::string, std::string>& snapshot_queries() {
  static const std::map<std::string, std::string> queries = {
      {"la_spatialunit",
       "SELECT parcel_id, layer_index, official_area, computed_area, repair_note, geom "
       "FROM la_spatialunit ORDER BY parcel_id"},
      {"building",
       "SELECT s.parcel_id, b.building_id, b.building_index, b.geom_kind, b.volume, "
       "b.eave_height, b.ridge_height, b.terrain_z, b.storeys, b.solid_valid, b.roof_area, "
       "b.roof_plan_area, b.wall_area, b.party_wall_area, b.ground_area, b.outer_ceiling_area, "
       "b.roof_dev_n, b.roof_dev_rmse, b.wall_dev_n, b.wall_dev_rmse, b.geom "
       "FROM building b JOIN la_spatialunit s ON s.fid = b.spatialunit_id ORDER BY b.building_id"},
      {"building_element",
       "SELECT b.building_id, e.element_index, e.element_type, e.area, e.plan_area, e.slope_deg, "
       "e.azimuth_deg, e.sigma_area, e.support_points, e.rmse, e.wall_evidence, e.geom "
       "FROM building_element e JOIN building b ON b.fid = e.building_fid "
       "ORDER BY b.building_id, e.element_index"},
      {"vm_valuation",
       "SELECT u.parcel_id, v.approach, v.currency, v.land_value, v.building_cost, "
       "v.sigma_building_cost, v.depreciation, v.building_value, v.njop, v.sigma_njop, "
       "v.taxable, v.tax, v.sigma_tax, v.note "
       "FROM vm_valuation v JOIN vm_valuationunit u ON u.fid = v.valuationunit_id "
       "ORDER BY u.parcel_id"},
      {"parcel_job",
       "SELECT parcel_id, layer_index, status, reason, inputs_key FROM parcel_job "
       "ORDER BY parcel_id"},
  };
  return queries;
}

inline Snapshot snapshot(const std::string& path) {
  Sqlite db(path);
  EXPECT_TRUE(db.ok()) << path << ": " << db.error();
  Snapshot s;
  for (const auto& [table, sql] : snapshot_queries()) s[table] = db.rows(sql);
  return s;
}

inline bool same_cell(const Cell& a, const Cell& b) {
  if (a.null || b.null) return a.null == b.null;
  if (a.number && b.number) return std::abs(a.d - b.d) <= 1e-9 * std::max(1.0, std::abs(a.d));
  return a.number == b.number && a.s == b.s;
}

inline std::string show(const Row& r) {
  std::string s;
  for (const auto& c : r) {
    if (!s.empty()) s += " | ";
    s += c.null ? "NULL" : c.s.size() > 40 ? "<" + std::to_string(c.s.size()) + " bytes>" : c.s;
  }
  return s;
}

// Empty when equal, else the first difference.
inline std::string diff_rows(const std::vector<Row>& a, const std::vector<Row>& b) {
  for (size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    bool same = a[i].size() == b[i].size();
    for (size_t c = 0; same && c < a[i].size(); ++c) same = same_cell(a[i][c], b[i][c]);
    if (!same) return "row " + std::to_string(i) + ":\n  " + show(a[i]) + "\n  " + show(b[i]);
  }
  if (a.size() != b.size())
    return std::to_string(a.size()) + " rows vs " + std::to_string(b.size());
  return "";
}

inline void expect_same_store(const Snapshot& a, const Snapshot& b, const std::string& what) {
  for (const auto& [table, rows] : a) {
    auto it = b.find(table);
    ASSERT_NE(it, b.end()) << table;
    EXPECT_EQ(diff_rows(rows, it->second), "") << what << ": table " << table;
  }
}

// Rows of one parcel in a snapshot table (first column is the parcel id where
// the table has one; building_element rows are matched by their building id prefix).
inline std::vector<Row> rows_of_parcel(const std::vector<Row>& rows, const std::string& parcel,
                                const std::set<std::string>& building_ids, bool by_building) {
  std::vector<Row> out;
  for (const auto& r : rows)
    if (by_building ? building_ids.count(r[0].s) > 0 : r[0].s == parcel) out.push_back(r);
  return out;
}

// ---------------------------------------------------------------------------
// A batch as a real child process that can be killed; with file_limit, no
// file it writes may grow past that many bytes (SIGXFSZ ignored, so a write
// past the limit fails as on a full disk).

inline pid_t spawn_cli(const std::string& args, const std::string& log, rlim_t file_limit = RLIM_INFINITY) {
  std::vector<std::string> argv_s{C3D_CLI_PATH};
  std::istringstream in(args);
  for (std::string a; in >> a;) argv_s.push_back(a);
  pid_t pid = fork();
  if (pid == 0) {
    int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      dup2(fd, 1);
      dup2(fd, 2);
      close(fd);
    }
    if (file_limit != RLIM_INFINITY) {
      signal(SIGXFSZ, SIG_IGN);
      rlimit lim{file_limit, file_limit};
      setrlimit(RLIMIT_FSIZE, &lim);
    }
    std::vector<char*> argv;
    for (auto& a : argv_s) argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(argv[0], argv.data());
    _exit(127);
  }
  return pid;
}

struct JobCounts {
  long done = -1, pending = -1;
};

inline JobCounts job_counts(const std::string& store) {
  JobCounts c;
  if (!fs::exists(store)) return c;
  Sqlite db(store);
  std::vector<Row> rows;
  if (!db.ok() ||
      !db.query("SELECT coalesce(sum(status <> 'pending'), 0), coalesce(sum(status = 'pending'), 0) "
                "FROM parcel_job",
                &rows) ||
      rows.empty())
    return c;
  c.done = long(rows[0][0].d);
  c.pending = long(rows[0][1].d);
  return c;
}

}  // namespace e2e
