#pragma once
// Thin RAII over the SQLite C API for the store: a connection and prepared
// statements with typed binds (NaN doubles become NULL, and back).
#include <sqlite3.h>

#include <cstdint>
#include <string>
#include <vector>

namespace c3d::sql {

class Db {
 public:
  Db() = default;
  Db(const std::string& path, bool read_only);
  ~Db();
  Db(const Db&) = delete;
  Db& operator=(const Db&) = delete;
  Db(Db&& o) noexcept : db_(o.db_), path_(std::move(o.path_)) { o.db_ = nullptr; }
  Db& operator=(Db&& o) noexcept;

  void exec(const std::string& sql);
  sqlite3* get() const { return db_; }
  const std::string& path() const { return path_; }
  std::int64_t last_id() const { return sqlite3_last_insert_rowid(db_); }
  [[noreturn]] void fail(const std::string& what) const;

 private:
  sqlite3* db_ = nullptr;
  std::string path_;
};

class Stmt {
 public:
  Stmt() = default;
  Stmt(const Db& db, const std::string& sql);
  ~Stmt();
  Stmt(const Stmt&) = delete;
  Stmt& operator=(const Stmt&) = delete;
  Stmt(Stmt&& o) noexcept : db_(o.db_), s_(o.s_) { o.s_ = nullptr; }
  Stmt& operator=(Stmt&& o) noexcept;

  // Binds in order starting at 1; reset() rewinds for the next row.
  Stmt& bind(double v);
  Stmt& bind(int v) { return bind(static_cast<long long>(v)); }
  Stmt& bind(long v) { return bind(static_cast<long long>(v)); }
  Stmt& bind(long long v);
  Stmt& bind(const std::string& v);
  Stmt& bind(const char* v) { return bind(std::string(v)); }
  Stmt& bind_blob(const std::vector<std::uint8_t>& b);  // empty -> NULL
  Stmt& bind_null();
  bool step();  // true while a row is available
  void run();   // step to completion, then reset
  void reset();

  bool is_null(int col) const { return sqlite3_column_type(s_, col) == SQLITE_NULL; }
  double get_double(int col) const;  // NULL -> NaN
  std::int64_t get_int(int col) const { return sqlite3_column_int64(s_, col); }
  std::string get_text(int col) const;
  const std::uint8_t* blob(int col, std::size_t* n) const;

 private:
  const Db* db_ = nullptr;
  sqlite3_stmt* s_ = nullptr;
  int next_ = 1;
};

// BEGIN IMMEDIATE ... COMMIT; rolls back when destroyed uncommitted (exception).
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
