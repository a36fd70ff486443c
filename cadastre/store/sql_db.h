#pragma once
// The store's database connection, one API over two backends: SQLite (the
// GeoPackage, a file path) and PostgreSQL + PostGIS (libpq, a
// `postgresql://` URL). A connection, prepared statements with typed binds
// (`?` placeholders; NaN doubles become NULL, and back), transactions.
// Geometry goes in and comes out as GeoPackage blobs on both: the PostgreSQL
// backend turns them into EWKB with the blob's srs_id as SRID, and a
// geometry column read back into a GeoPackage blob again.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

struct sqlite3;

namespace c3d::sql {

class Backend;
class Cursor;

// True for a `postgresql://` or `postgres://` URL, or GDAL's `PG:` followed
// by libpq's keyword=value connection string.
bool is_postgres_url(const std::string& loc);
// What libpq connects with: the URL, or the connection string after `PG:`.
std::string libpq_conninfo(const std::string& loc);
// The location as messages name it: a password masked.
std::string display_name(const std::string& loc);
// Throws InputError where a store location that is no PostgreSQL location
// reads as one (another URL scheme, libpq keywords without `PG:`): a
// GeoPackage would be written under that name.
void check_store_location(const std::string& loc);

class Db {
 public:
  Db();
  // A file path opens SQLite; a PostgreSQL URL connects with libpq. Throws
  // InputError naming the location when it cannot.
  Db(const std::string& loc, bool read_only);
  ~Db();
  Db(const Db&) = delete;
  Db& operator=(const Db&) = delete;
  Db(Db&& o) noexcept;
  Db& operator=(Db&& o) noexcept;

  void exec(const std::string& sql);  // several statements, no result
  bool postgres() const;
  sqlite3* get() const;  // nullptr on PostgreSQL
  const std::string& path() const { return loc_; }  // the location as given
  std::int64_t last_id() const;  // key of the last row inserted on this connection
  bool has_table(const std::string& table) const;
  [[noreturn]] void fail(const std::string& what) const;
  Backend& backend() const { return *b_; }

 private:
  std::unique_ptr<Backend> b_;
  std::string loc_;
};

class Stmt {
 public:
  Stmt();
  Stmt(const Db& db, const std::string& sql);
  ~Stmt();
  Stmt(const Stmt&) = delete;
  Stmt& operator=(const Stmt&) = delete;
  Stmt(Stmt&& o) noexcept;
  Stmt& operator=(Stmt&& o) noexcept;

  // Binds in order starting at 1; reset() rewinds for the next row.
  Stmt& bind(double v);
  Stmt& bind(int v) { return bind(static_cast<long long>(v)); }
  Stmt& bind(long v) { return bind(static_cast<long long>(v)); }
  Stmt& bind(long long v);
  Stmt& bind(const std::string& v);
  Stmt& bind(const char* v) { return bind(std::string(v)); }
  Stmt& bind_blob(const std::vector<std::uint8_t>& b);  // a GeoPackage geometry blob; empty -> NULL
  Stmt& bind_null();
  bool step();  // true while a row is available
  void run();   // step to completion, then reset
  void reset();

  bool is_null(int col) const;
  double get_double(int col) const;  // NULL -> NaN
  std::int64_t get_int(int col) const;  // NULL -> 0; a boolean -> 0 / 1
  std::string get_text(int col) const;  // NULL -> ""
  const std::uint8_t* blob(int col, std::size_t* n) const;

  // The same, by the column's name in the result (after a step); a name the
  // result lacks is a programming error (std::logic_error).
  int col(const std::string& name) const;
  bool is_null(const std::string& name) const { return is_null(col(name)); }
  double get_double(const std::string& name) const { return get_double(col(name)); }
  std::int64_t get_int(const std::string& name) const { return get_int(col(name)); }
  std::string get_text(const std::string& name) const { return get_text(col(name)); }
  const std::uint8_t* blob(const std::string& name, std::size_t* n) const { return blob(col(name), n); }

 private:
  std::unique_ptr<Cursor> c_;
  mutable std::vector<std::string> names_;  // the result's column names, read once
  int next_ = 1;
};

// BEGIN ... COMMIT (SQLite: BEGIN IMMEDIATE); rolls back when destroyed
// uncommitted (exception).
class Transaction {
 public:
  explicit Transaction(Db& db);
  ~Transaction();
  void commit();

 private:
  Db& db_;
  bool done_ = false;
};

}  // namespace c3d::sql
