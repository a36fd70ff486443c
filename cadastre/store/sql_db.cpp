#include "cadastre/store/sql_db.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "cadastre/store/sql_backend.h"
#include "core/error.h"

namespace c3d::sql {

namespace {

// GDAL's PostgreSQL source, its prefix in either case.
bool is_gdal_pg(const std::string& loc) {
  return loc.size() >= 3 && (loc.compare(0, 3, "PG:") == 0 || loc.compare(0, 3, "pg:") == 0);
}

// A connection string's password=... (quoted or not) masked.
std::string masked_conninfo(const std::string& loc) {
  const size_t key = loc.find("password=");
  if (key == std::string::npos) return loc;
  const size_t start = key + 9;
  size_t end = start;
  if (end < loc.size() && loc[end] == '\'') {
    for (++end; end < loc.size() && loc[end] != '\''; ++end)
      if (loc[end] == '\\') ++end;
    end = std::min(loc.size(), end + 1);
  } else {
    while (end < loc.size() && loc[end] != ' ') ++end;
  }
  return loc.substr(0, start) + "***" + loc.substr(end);
}

}  // namespace

bool is_postgres_url(const std::string& loc) {
  return loc.rfind("postgresql://", 0) == 0 || loc.rfind("postgres://", 0) == 0 || is_gdal_pg(loc);
}

std::string libpq_conninfo(const std::string& loc) { return is_gdal_pg(loc) ? loc.substr(3) : loc; }

void check_store_location(const std::string& loc) {
  if (is_postgres_url(loc)) return;
  const size_t scheme = loc.find("://");
  const bool url = scheme != std::string::npos && scheme > 0 &&
                   loc.find_first_of("/\\ ") == scheme + 1;  // no path before the scheme's colon
  if (url)
    throw InputError(loc, "not a store location this reads: give a GeoPackage path, postgresql://... or PG:...");
  for (const char* key : {"dbname=", "host=", "user=", "port=", "service="})
    if (loc.rfind(key, 0) == 0 || loc.find(std::string(" ") + key) != std::string::npos)
      throw InputError(masked_conninfo(loc),
                       "reads as a PostgreSQL connection string: give it as PG:<connection string> "
                       "(GDAL's form) or as postgresql://...");
}

std::string display_name(const std::string& loc) {
  if (is_gdal_pg(loc)) return masked_conninfo(loc);
  if (!is_postgres_url(loc)) return loc;
  // postgresql://user:secret@host/db -> postgresql://user:***@host/db
  const size_t start = loc.find("://") + 3, at = loc.find('@', start);
  if (at == std::string::npos) return loc;
  const size_t colon = loc.find(':', start);
  if (colon == std::string::npos || colon > at) return loc;
  return loc.substr(0, colon + 1) + "***" + loc.substr(at);
}

Db::Db() = default;
Db::Db(const std::string& loc, bool read_only) : loc_(loc) {
  check_store_location(loc);
  b_ = is_postgres_url(loc) ? open_postgres(loc) : open_sqlite(loc, read_only);
}
Db::~Db() = default;
Db::Db(Db&& o) noexcept = default;
Db& Db::operator=(Db&& o) noexcept = default;

void Db::exec(const std::string& sql) { b_->exec(sql); }
bool Db::postgres() const { return b_ && b_->sqlite() == nullptr; }
sqlite3* Db::get() const { return b_ ? b_->sqlite() : nullptr; }
std::int64_t Db::last_id() const { return b_->last_id(); }
bool Db::has_table(const std::string& table) const { return b_->has_table(table); }

void Db::fail(const std::string& what) const { throw InputError(display_name(loc_), what + ": " + b_->error()); }

Stmt::Stmt() = default;
Stmt::Stmt(const Db& db, const std::string& sql) : c_(db.backend().prepare(sql)) {}
Stmt::~Stmt() = default;
Stmt::Stmt(Stmt&& o) noexcept = default;
Stmt& Stmt::operator=(Stmt&& o) noexcept = default;

Stmt& Stmt::bind(double v) {
  if (std::isfinite(v)) c_->bind_double(next_++ - 1, v);
  else c_->bind_null(next_++ - 1);
  return *this;
}

Stmt& Stmt::bind(long long v) {
  c_->bind_int(next_++ - 1, v);
  return *this;
}

Stmt& Stmt::bind(const std::string& v) {
  c_->bind_text(next_++ - 1, v);
  return *this;
}

Stmt& Stmt::bind_blob(const std::vector<std::uint8_t>& b) {
  if (b.empty()) return bind_null();
  c_->bind_geometry(next_++ - 1, b);
  return *this;
}

Stmt& Stmt::bind_null() {
  c_->bind_null(next_++ - 1);
  return *this;
}

bool Stmt::step() { return c_->step(); }

void Stmt::run() {
  while (step()) {
  }
  reset();
}

void Stmt::reset() {
  c_->reset();
  next_ = 1;
}

bool Stmt::is_null(int col) const { return c_->is_null(col); }
double Stmt::get_double(int col) const {
  return is_null(col) ? std::numeric_limits<double>::quiet_NaN() : c_->get_double(col);
}
std::int64_t Stmt::get_int(int col) const { return is_null(col) ? 0 : c_->get_int(col); }
std::string Stmt::get_text(int col) const { return is_null(col) ? std::string() : c_->get_text(col); }
const std::uint8_t* Stmt::blob(int col, std::size_t* n) const {
  if (is_null(col)) {
    *n = 0;
    return nullptr;
  }
  return c_->blob(col, n);
}

int Stmt::col(const std::string& name) const {
  if (names_.empty()) names_ = c_->column_names();
  for (size_t i = 0; i < names_.size(); ++i)
    if (names_[i] == name) return int(i);
  throw std::logic_error("no column '" + name + "' in this statement's result");
}

Transaction::Transaction(Db& db) : db_(db) { db_.backend().begin(); }

Transaction::~Transaction() {
  if (!done_) db_.backend().rollback();
}

void Transaction::commit() {
  db_.exec("COMMIT");
  done_ = true;
}

}  // namespace c3d::sql
