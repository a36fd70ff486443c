// The PostgreSQL backend of cadastre/store/sql_db.h (libpq). Statements are
// prepared on the server with `?` turned into `$n`; values travel as text
// (doubles with 17 significant digits: exact), geometry as hex EWKB.
#include <libpq-fe.h>

#include <cstdio>
#include <cctype>
#include <cstdlib>
#include <cstring>
#include <map>

#include "cadastre/store/sql_backend.h"
#include "cadastre/store/sql_db.h"
#include "core/error.h"
#include "core/log.h"

namespace c3d::sql {

std::string display_name(const std::string& loc);

namespace {

constexpr std::uint32_t kEwkbZ = 0x80000000u, kEwkbM = 0x40000000u, kEwkbSrid = 0x20000000u;

std::string first_line(const char* msg) {
  std::string s = msg ? msg : "";
  s = s.substr(0, s.find('\n'));
  return s.empty() ? "unknown error" : s;
}

std::uint32_t read_u32(const std::uint8_t* p, bool little) {
  std::uint32_t v = 0;
  for (int k = 0; k < 4; ++k) v |= std::uint32_t(p[little ? k : 3 - k]) << (8 * k);
  return v;
}

void write_u32(std::uint8_t* p, std::uint32_t v, bool little) {
  for (int k = 0; k < 4; ++k) p[little ? k : 3 - k] = std::uint8_t(v >> (8 * k));
}

// GeoPackage blob (header, ISO WKB) -> hex EWKB with the header's srs_id as
// SRID (none where it is <= 0: undefined). Nested parts keep their ISO codes,
// which PostGIS reads too.
std::string gpkg_to_hex_ewkb(const std::vector<std::uint8_t>& b) {
  static const int kEnvelopeBytes[] = {0, 32, 48, 48, 64};
  if (b.size() < 8 || b[0] != 'G' || b[1] != 'P') throw std::runtime_error("not a GeoPackage geometry blob");
  const int env = (b[3] >> 1) & 7;
  if (env > 4) throw std::runtime_error("bad GeoPackage envelope code");
  const std::int32_t srs = std::int32_t(read_u32(&b[4], (b[3] & 1) != 0));
  const size_t at = 8 + size_t(kEnvelopeBytes[env]);
  if (b.size() < at + 5) throw std::runtime_error("short GeoPackage geometry blob");
  const bool little = b[at] == 1;
  const std::uint32_t iso = read_u32(&b[at + 1], little);
  const std::uint32_t kind = iso / 1000;
  std::uint32_t type = iso % 1000;
  if (kind == 1 || kind == 3) type |= kEwkbZ;
  if (kind == 2 || kind == 3) type |= kEwkbM;
  if (srs > 0) type |= kEwkbSrid;
  std::vector<std::uint8_t> out(b.begin() + long(at), b.begin() + long(at) + 5);
  write_u32(&out[1], type, little);
  if (srs > 0) {
    out.resize(9);
    write_u32(&out[5], std::uint32_t(srs), little);
  }
  out.insert(out.end(), b.begin() + long(at) + 5, b.end());
  static const char* kHex = "0123456789ABCDEF";
  std::string hex;
  hex.reserve(out.size() * 2);
  for (std::uint8_t c : out) hex += kHex[c >> 4], hex += kHex[c & 15];
  return hex;
}

int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  throw std::runtime_error("bad hex digit in a geometry");
}

// PostGIS's text form of a geometry (hex EWKB) -> GeoPackage blob: the SRID
// moves into the header (no envelope), the Z flags stay (the reader knows them).
std::vector<std::uint8_t> hex_ewkb_to_gpkg(const char* text, size_t len) {
  std::vector<std::uint8_t> w;
  for (size_t i = 0; i + 1 < len; i += 2) w.push_back(std::uint8_t(hex_value(text[i]) * 16 + hex_value(text[i + 1])));
  if (w.size() < 5) throw std::runtime_error("short geometry from PostgreSQL");
  const bool little = w[0] == 1;
  std::uint32_t type = read_u32(&w[1], little);
  std::uint32_t srid = 0;
  if (type & kEwkbSrid) {
    if (w.size() < 9) throw std::runtime_error("short geometry from PostgreSQL");
    srid = read_u32(&w[5], little);
    w.erase(w.begin() + 5, w.begin() + 9);
    write_u32(&w[1], type & ~kEwkbSrid, little);
  }
  std::vector<std::uint8_t> out = {'G', 'P', 0, 1, 0, 0, 0, 0};
  write_u32(&out[4], srid, true);
  out.insert(out.end(), w.begin(), w.end());
  return out;
}

// `?` -> `$1`, `$2`, ...; `?N` -> `$N`; quoted text left alone.
std::string numbered_placeholders(const std::string& sql) {
  std::string out;
  int next = 0;
  char quote = 0;
  for (size_t i = 0; i < sql.size(); ++i) {
    const char c = sql[i];
    if (quote) {
      if (c == quote) quote = 0;
      out += c;
    } else if (c == '\'' || c == '"') {
      quote = c;
      out += c;
    } else if (c == '?') {
      const bool numbered = i + 1 < sql.size() && std::isdigit(static_cast<unsigned char>(sql[i + 1]));
      out += numbered ? "$" : "$" + std::to_string(++next);
    } else {
      out += c;
    }
  }
  return out;
}

// An INSERT into one of the store's tables (all keyed by `fid`) returns its
// key at once: last_id() then needs no round trip of its own.
bool returns_fid(const std::string& sql) {
  if (sql.rfind("INSERT INTO ", 0) != 0 || sql.find("RETURNING") != std::string::npos) return false;
  for (const char* other : {"INSERT INTO layer_styles", "INSERT INTO spatial_ref_sys"})
    if (sql.rfind(other, 0) == 0) return false;
  return true;
}

void quiet_notices(void*, const char* message) { log::debug(std::string("postgresql: ") + first_line(message)); }

class PgCursor : public Cursor {
 public:
  // last_insert: where an INSERT's returned key goes (0: none came back).
  PgCursor(PGconn* conn, const std::string& where, const std::string& sql, int id, std::int64_t* last_insert)
      : conn_(conn), where_(where), name_("c3d_" + std::to_string(id)), sql_(sql.substr(0, 120)),
        last_insert_(returns_fid(sql) ? last_insert : nullptr) {
    const std::string text = numbered_placeholders(sql) + (last_insert_ ? " RETURNING fid" : "");
    PGresult* r = PQprepare(conn_, name_.c_str(), text.c_str(), 0, nullptr);
    const bool ok = PQresultStatus(r) == PGRES_COMMAND_OK;
    const std::string msg = ok ? "" : first_line(PQresultErrorMessage(r));
    PQclear(r);
    if (!ok) throw InputError(where_, "cannot prepare [" + sql_ + "]: " + msg);
  }
  ~PgCursor() override {
    PQclear(res_);
    PQclear(PQexec(conn_, ("DEALLOCATE " + name_).c_str()));  // fails harmlessly in an aborted transaction
  }

  void bind_double(int i, double v) override {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    set(i, buf);
  }
  void bind_int(int i, long long v) override { set(i, std::to_string(v)); }
  void bind_text(int i, const std::string& v) override { set(i, v); }
  void bind_geometry(int i, const std::vector<std::uint8_t>& b) override { set(i, gpkg_to_hex_ewkb(b)); }
  void bind_null(int i) override {
    if (size_t(i) >= values_.size()) values_.resize(size_t(i) + 1), null_.resize(size_t(i) + 1, true);
    null_[size_t(i)] = true;
  }

  bool step() override {
    if (!res_) execute();
    return ++row_ < PQntuples(res_);
  }
  void reset() override {
    PQclear(res_);
    res_ = nullptr;
    row_ = -1;
    values_.clear();
    null_.clear();
    blobs_.clear();
  }

  std::vector<std::string> column_names() const override {
    std::vector<std::string> out;
    for (int i = 0; res_ && i < PQnfields(res_); ++i) out.emplace_back(PQfname(res_, i));
    return out;
  }
  bool is_null(int col) const override { return PQgetisnull(res_, row_, col) != 0; }
  double get_double(int col) const override { return std::strtod(PQgetvalue(res_, row_, col), nullptr); }
  std::int64_t get_int(int col) const override {
    const char* v = PQgetvalue(res_, row_, col);
    if (v[0] == 't') return 1;  // boolean
    if (v[0] == 'f') return 0;
    return std::strtoll(v, nullptr, 10);
  }
  std::string get_text(int col) const override {
    return std::string(PQgetvalue(res_, row_, col), size_t(PQgetlength(res_, row_, col)));
  }
  const std::uint8_t* blob(int col, std::size_t* n) const override {
    auto& b = blobs_[col] = hex_ewkb_to_gpkg(PQgetvalue(res_, row_, col), size_t(PQgetlength(res_, row_, col)));
    *n = b.size();
    return b.data();
  }

 private:
  void set(int i, std::string v) {
    if (size_t(i) >= values_.size()) values_.resize(size_t(i) + 1), null_.resize(size_t(i) + 1, true);
    values_[size_t(i)] = std::move(v);
    null_[size_t(i)] = false;
  }
  void execute() {
    std::vector<const char*> p(values_.size());
    for (size_t k = 0; k < p.size(); ++k) p[k] = null_[k] ? nullptr : values_[k].c_str();
    res_ = PQexecPrepared(conn_, name_.c_str(), int(p.size()), p.data(), nullptr, nullptr, 0);
    const auto st = PQresultStatus(res_);
    if (st != PGRES_TUPLES_OK && st != PGRES_COMMAND_OK) {
      const std::string msg = first_line(PQresultErrorMessage(res_));
      reset();
      throw InputError(where_, "SQL failed [" + sql_ + "]: " + msg);
    }
    if (last_insert_) *last_insert_ = PQntuples(res_) == 1 ? std::strtoll(PQgetvalue(res_, 0, 0), nullptr, 10) : 0;
  }

  PGconn* conn_;
  std::string where_, name_, sql_;
  std::int64_t* last_insert_;
  PGresult* res_ = nullptr;
  int row_ = -1;
  std::vector<std::string> values_;
  std::vector<bool> null_;
  mutable std::map<int, std::vector<std::uint8_t>> blobs_;
};

class PgBackend : public Backend {
 public:
  explicit PgBackend(const std::string& url) : where_(display_name(url)) {
    conn_ = PQconnectdb(libpq_conninfo(url).c_str());
    if (!conn_ || PQstatus(conn_) != CONNECTION_OK) {
      const std::string msg = first_line(conn_ ? PQerrorMessage(conn_) : "out of memory");
      PQfinish(conn_);
      conn_ = nullptr;
      throw InputError(where_, "cannot connect to the PostgreSQL store: " + msg);
    }
    PQsetNoticeProcessor(conn_, quiet_notices, nullptr);
    exec("SET client_min_messages = warning; SET extra_float_digits = 3");
  }
  ~PgBackend() override { PQfinish(conn_); }

  void exec(const std::string& sql) override {
    last_insert_ = 0;  // an INSERT in here returns no key: last_id() asks the server
    PGresult* r = PQexec(conn_, sql.c_str());
    const auto st = PQresultStatus(r);
    const bool ok = st == PGRES_COMMAND_OK || st == PGRES_TUPLES_OK;
    const std::string msg = ok ? "" : first_line(PQresultErrorMessage(r));
    PQclear(r);
    if (!ok) throw InputError(where_, "SQL failed: " + msg + " [" + sql.substr(0, 120) + "]");
  }
  std::unique_ptr<Cursor> prepare(const std::string& sql) override {
    return std::make_unique<PgCursor>(conn_, where_, sql, ++statements_, &last_insert_);
  }
  std::int64_t last_id() override {
    if (last_insert_ > 0) return last_insert_;  // RETURNING fid of the last INSERT
    PGresult* r = PQexec(conn_, "SELECT lastval()");
    const bool ok = PQresultStatus(r) == PGRES_TUPLES_OK && PQntuples(r) == 1;
    const std::int64_t id = ok ? std::strtoll(PQgetvalue(r, 0, 0), nullptr, 10) : 0;
    const std::string msg = ok ? "" : first_line(PQresultErrorMessage(r));
    PQclear(r);
    if (!ok) throw InputError(where_, "no key of the last row: " + msg);
    return id;
  }
  std::string error() const override { return first_line(PQerrorMessage(conn_)); }
  void begin() override { exec("BEGIN"); }
  void rollback() noexcept override { PQclear(PQexec(conn_, "ROLLBACK")); }
  bool has_table(const std::string& table) override {
    PgCursor q(conn_, where_, "SELECT 1 WHERE to_regclass(?) IS NOT NULL", ++statements_, nullptr);
    q.bind_text(0, table);
    return q.step();
  }

 private:
  std::string where_;
  PGconn* conn_ = nullptr;
  int statements_ = 0;
  std::int64_t last_insert_ = 0;
};

}  // namespace

std::unique_ptr<Backend> open_postgres(const std::string& url) { return std::make_unique<PgBackend>(url); }

}  // namespace c3d::sql
