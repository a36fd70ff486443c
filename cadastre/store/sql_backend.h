#pragma once
// The two halves a backend of cadastre/store/sql_db.h implements (internal):
// a connection and a prepared statement. Columns and binds count from 0.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

struct sqlite3;

namespace c3d::sql {

class Cursor {
 public:
  virtual ~Cursor() = default;
  virtual void bind_double(int i, double v) = 0;  // finite values only
  virtual void bind_int(int i, long long v) = 0;
  virtual void bind_text(int i, const std::string& v) = 0;
  virtual void bind_geometry(int i, const std::vector<std::uint8_t>& gpkg_blob) = 0;
  virtual void bind_null(int i) = 0;
  virtual bool step() = 0;
  virtual void reset() = 0;
  virtual bool is_null(int col) const = 0;
  virtual double get_double(int col) const = 0;
  virtual std::int64_t get_int(int col) const = 0;
  virtual std::string get_text(int col) const = 0;
  virtual const std::uint8_t* blob(int col, std::size_t* n) const = 0;
  // The result's column names (a SELECT's `AS` names); PostgreSQL knows them once a step ran.
  virtual std::vector<std::string> column_names() const = 0;
};

class Backend {
 public:
  virtual ~Backend() = default;
  virtual void exec(const std::string& sql) = 0;
  virtual std::unique_ptr<Cursor> prepare(const std::string& sql) = 0;
  virtual std::int64_t last_id() = 0;
  virtual std::string error() const = 0;  // the last error, one line
  virtual void begin() = 0;
  virtual void rollback() noexcept = 0;
  virtual bool has_table(const std::string& table) = 0;
  virtual sqlite3* sqlite() const { return nullptr; }
};

std::unique_ptr<Backend> open_sqlite(const std::string& path, bool read_only);
std::unique_ptr<Backend> open_postgres(const std::string& url);

}  // namespace c3d::sql
