#include "cadastre/sqlite_util.h"

#include <cmath>
#include <limits>

#include "core/error.h"

namespace c3d::sql {

Db::Db(const std::string& path, bool read_only) : path_(path) {
  int flags = read_only ? SQLITE_OPEN_READONLY : (SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
  if (sqlite3_open_v2(path.c_str(), &db_, flags, nullptr) != SQLITE_OK) {
    std::string msg = db_ ? sqlite3_errmsg(db_) : "out of memory";
    sqlite3_close(db_);
    db_ = nullptr;
    throw InputError(path, "cannot open SQLite database: " + msg);
  }
  sqlite3_busy_timeout(db_, 10000);
}

Db::~Db() { sqlite3_close_v2(db_); }

Db& Db::operator=(Db&& o) noexcept {
  if (this != &o) {
    sqlite3_close_v2(db_);
    db_ = o.db_;
    path_ = std::move(o.path_);
    o.db_ = nullptr;
  }
  return *this;
}

namespace {

// SQLite's words for a failed write, and what a user can do about it.
std::string write_hint(sqlite3* db) {
  const int code = sqlite3_errcode(db);
  return code == SQLITE_FULL || code == SQLITE_IOERR ? " (is the disk full?)" : "";
}

}  // namespace

void Db::fail(const std::string& what) const {
  throw InputError(path_, what + ": " + sqlite3_errmsg(db_) + write_hint(db_));
}

void Db::exec(const std::string& sql) {
  char* err = nullptr;
  if (sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &err) != SQLITE_OK) {
    std::string msg = err ? err : "?";
    sqlite3_free(err);
    throw InputError(path_, "SQL failed: " + msg + write_hint(db_) + " [" + sql.substr(0, 120) + "]");
  }
}

Stmt::Stmt(const Db& db, const std::string& sql) : db_(&db) {
  if (sqlite3_prepare_v3(db.get(), sql.c_str(), -1, SQLITE_PREPARE_PERSISTENT, &s_, nullptr) !=
      SQLITE_OK)
    db.fail("cannot prepare [" + sql.substr(0, 120) + "]");
}

Stmt::~Stmt() { sqlite3_finalize(s_); }

Stmt& Stmt::operator=(Stmt&& o) noexcept {
  if (this != &o) {
    sqlite3_finalize(s_);
    db_ = o.db_;
    s_ = o.s_;
    next_ = o.next_;
    o.s_ = nullptr;
  }
  return *this;
}

Stmt& Stmt::bind(double v) {
  if (std::isfinite(v)) sqlite3_bind_double(s_, next_++, v);
  else sqlite3_bind_null(s_, next_++);
  return *this;
}

Stmt& Stmt::bind(long long v) {
  sqlite3_bind_int64(s_, next_++, v);
  return *this;
}

Stmt& Stmt::bind(const std::string& v) {
  sqlite3_bind_text(s_, next_++, v.data(), int(v.size()), SQLITE_TRANSIENT);
  return *this;
}

Stmt& Stmt::bind_blob(const std::vector<std::uint8_t>& b) {
  if (b.empty()) return bind_null();
  sqlite3_bind_blob(s_, next_++, b.data(), int(b.size()), SQLITE_TRANSIENT);
  return *this;
}

Stmt& Stmt::bind_null() {
  sqlite3_bind_null(s_, next_++);
  return *this;
}

bool Stmt::step() {
  int rc = sqlite3_step(s_);
  if (rc == SQLITE_ROW) return true;
  if (rc == SQLITE_DONE) return false;
  std::string sql = sqlite3_sql(s_) ? sqlite3_sql(s_) : "";
  sqlite3_reset(s_);
  db_->fail("SQL step failed [" + sql.substr(0, 120) + "]");
}

void Stmt::run() {
  while (step()) {
  }
  reset();
}

void Stmt::reset() {
  sqlite3_reset(s_);
  sqlite3_clear_bindings(s_);
  next_ = 1;
}

double Stmt::get_double(int col) const {
  return is_null(col) ? std::numeric_limits<double>::quiet_NaN() : sqlite3_column_double(s_, col);
}

std::string Stmt::get_text(int col) const {
  auto p = sqlite3_column_text(s_, col);
  return p ? std::string(reinterpret_cast<const char*>(p), size_t(sqlite3_column_bytes(s_, col)))
           : std::string();
}

const std::uint8_t* Stmt::blob(int col, std::size_t* n) const {
  auto p = static_cast<const std::uint8_t*>(sqlite3_column_blob(s_, col));
  *n = size_t(sqlite3_column_bytes(s_, col));
  return p;
}

Transaction::Transaction(Db& db) : db_(db) { db_.exec("BEGIN IMMEDIATE"); }

Transaction::~Transaction() {
  if (!done_) sqlite3_exec(db_.get(), "ROLLBACK", nullptr, nullptr, nullptr);
}

void Transaction::commit() {
  db_.exec("COMMIT");
  done_ = true;
}

}  // namespace c3d::sql
