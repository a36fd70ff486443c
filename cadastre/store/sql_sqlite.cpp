// The SQLite backend of cadastre/store/sql_db.h: the GeoPackage file.
#include <sqlite3.h>

#include <cstdio>
#include <filesystem>

#include "cadastre/store/sql_backend.h"
#include "core/error.h"

namespace c3d::sql {

namespace {

// SQLite's words for a failed write, and what a user can do about it.
std::string write_hint(sqlite3* db) {
  const int code = sqlite3_errcode(db);
  return code == SQLITE_FULL || code == SQLITE_IOERR ? " (is the disk full?)" : "";
}

// A file path as a URI's path: the characters a URI gives meaning escaped.
std::string uri_path(const std::string& path) {
  std::string out;
  for (unsigned char c : path) {
    if (c == '%' || c == '?' || c == '#' || c <= ' ' || c >= 0x7f) {
      char hex[4];
      std::snprintf(hex, sizeof hex, "%%%02X", c);
      out += hex;
    } else {
      out += char(c);
    }
  }
  return out;
}

class SqliteCursor : public Cursor {
 public:
  SqliteCursor(sqlite3* db, const std::string& path, const std::string& sql) : db_(db), path_(path) {
    if (sqlite3_prepare_v3(db, sql.c_str(), -1, SQLITE_PREPARE_PERSISTENT, &s_, nullptr) != SQLITE_OK)
      throw InputError(path_, "cannot prepare [" + sql.substr(0, 120) + "]: " + sqlite3_errmsg(db));
  }
  ~SqliteCursor() override { sqlite3_finalize(s_); }

  void bind_double(int i, double v) override { sqlite3_bind_double(s_, i + 1, v); }
  void bind_int(int i, long long v) override { sqlite3_bind_int64(s_, i + 1, v); }
  void bind_text(int i, const std::string& v) override {
    sqlite3_bind_text(s_, i + 1, v.data(), int(v.size()), SQLITE_TRANSIENT);
  }
  void bind_geometry(int i, const std::vector<std::uint8_t>& b) override {
    sqlite3_bind_blob(s_, i + 1, b.data(), int(b.size()), SQLITE_TRANSIENT);
  }
  void bind_null(int i) override { sqlite3_bind_null(s_, i + 1); }

  bool step() override {
    const int rc = sqlite3_step(s_);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    const std::string sql = sqlite3_sql(s_) ? sqlite3_sql(s_) : "";
    sqlite3_reset(s_);
    throw InputError(path_, "SQL step failed [" + sql.substr(0, 120) + "]: " + sqlite3_errmsg(db_) +
                                write_hint(db_));
  }
  void reset() override {
    sqlite3_reset(s_);
    sqlite3_clear_bindings(s_);
  }

  std::vector<std::string> column_names() const override {
    std::vector<std::string> out;
    for (int i = 0; i < sqlite3_column_count(s_); ++i) out.emplace_back(sqlite3_column_name(s_, i));
    return out;
  }
  bool is_null(int col) const override { return sqlite3_column_type(s_, col) == SQLITE_NULL; }
  double get_double(int col) const override { return sqlite3_column_double(s_, col); }
  std::int64_t get_int(int col) const override { return sqlite3_column_int64(s_, col); }
  std::string get_text(int col) const override {
    auto p = sqlite3_column_text(s_, col);
    return p ? std::string(reinterpret_cast<const char*>(p), size_t(sqlite3_column_bytes(s_, col)))
             : std::string();
  }
  const std::uint8_t* blob(int col, std::size_t* n) const override {
    auto p = static_cast<const std::uint8_t*>(sqlite3_column_blob(s_, col));
    *n = size_t(sqlite3_column_bytes(s_, col));
    return p;
  }

 private:
  sqlite3* db_;
  const std::string& path_;
  sqlite3_stmt* s_ = nullptr;
};

class SqliteBackend : public Backend {
 public:
  SqliteBackend(const std::string& path, bool read_only) : path_(path) {
    open(path.c_str(), read_only ? SQLITE_OPEN_READONLY : (SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE));
    try {
      if (read_only && !readable()) open_immutable();
    } catch (...) {  // no destructor runs for a constructor that throws
      sqlite3_close(db_);
      throw;
    }
    sqlite3_busy_timeout(db_, 10000);
  }
  ~SqliteBackend() override { sqlite3_close_v2(db_); }

  void exec(const std::string& sql) override {
    char* err = nullptr;
    if (sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &err) != SQLITE_OK) {
      std::string msg = err ? err : "?";
      sqlite3_free(err);
      throw InputError(path_, "SQL failed: " + msg + write_hint(db_) + " [" + sql.substr(0, 120) + "]");
    }
  }
  std::unique_ptr<Cursor> prepare(const std::string& sql) override {
    return std::make_unique<SqliteCursor>(db_, path_, sql);
  }
  std::int64_t last_id() override { return sqlite3_last_insert_rowid(db_); }
  std::string error() const override { return sqlite3_errmsg(db_) + write_hint(db_); }
  void begin() override { exec("BEGIN IMMEDIATE"); }
  void rollback() noexcept override { sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr); }
  bool has_table(const std::string& table) override {
    SqliteCursor q(db_, path_, "SELECT 1 FROM sqlite_master WHERE type='table' AND name=?");
    q.bind_text(0, table);
    return q.step();
  }
  sqlite3* sqlite() const override { return db_; }

 private:
  void open(const char* name, int flags) {
    if (sqlite3_open_v2(name, &db_, flags, nullptr) != SQLITE_OK) {
      std::string msg = db_ ? sqlite3_errmsg(db_) : "out of memory";
      sqlite3_close(db_);
      db_ = nullptr;
      throw InputError(path_, "cannot open SQLite database: " + msg);
    }
  }
  // Whether the schema reads: a store left in WAL mode (a run killed before
  // it closed, or an earlier version's) cannot be read where its folder is
  // read-only, as SQLite cannot make the -shm file there.
  bool readable() {
    return sqlite3_exec(db_, "SELECT count(*) FROM sqlite_master", nullptr, nullptr, nullptr) == SQLITE_OK;
  }
  // Read-only media: the file as it is, no locks and no WAL index. Writes
  // still in a -wal file beside it would go unread, so such a store is refused.
  void open_immutable() {
    std::error_code ec;
    if (std::filesystem::file_size(path_ + "-wal", ec) > 0 && !ec)
      throw InputError(path_, "cannot open SQLite database: its folder is read-only and " + path_ +
                                  "-wal holds writes not yet in it; copy both to writable storage");
    sqlite3_close(db_);
    db_ = nullptr;
    open(("file:" + uri_path(path_) + "?immutable=1").c_str(), SQLITE_OPEN_READONLY | SQLITE_OPEN_URI);
    if (!readable()) throw InputError(path_, std::string("cannot open SQLite database: ") + sqlite3_errmsg(db_));
  }

  std::string path_;
  sqlite3* db_ = nullptr;
};

}  // namespace

std::unique_ptr<Backend> open_sqlite(const std::string& path, bool read_only) {
  return std::make_unique<SqliteBackend>(path, read_only);
}

}  // namespace c3d::sql
