// Reading a store back: the batch model, valuations, jobs and runs.
#include "cadastre/store/store.h"

#include <algorithm>
#include <filesystem>
#include <unordered_map>
#include <nlohmann/json.hpp>

#include "cadastre/store/gpkg_geometry.h"
#include "cadastre/store/lods.h"
#include "cadastre/store/schema.h"
#include "cadastre/store/sql_db.h"
#include "core/error.h"

namespace c3d {

namespace {

std::vector<Timing> parse_timings(const std::string& text) {
  std::vector<Timing> out;
  if (text.empty()) return out;
  auto j = nlohmann::json::parse(text, nullptr, false);
  if (!j.is_array()) return out;
  for (const auto& e : j) out.push_back({e.value("stage", ""), e.value("seconds", 0.0)});
  return out;
}

ElementType element_type_from(const std::string& s) {
  for (ElementType t : {ElementType::Roof, ElementType::Wall, ElementType::PartyWall,
                        ElementType::Ground, ElementType::OuterCeiling})
    if (s == to_string(t)) return t;
  throw InputError("store", "unknown element type '" + s + "'");
}

WallEvidence evidence_from(const std::string& s) {
  for (WallEvidence e : {WallEvidence::None, WallEvidence::Measured, WallEvidence::Propagated,
                         WallEvidence::Default, WallEvidence::ParcelBoundary, WallEvidence::RoofStep})
    if (s == to_string(e)) return e;
  return WallEvidence::None;
}

// What parse() makes of a row's text; text it refuses (std::invalid_argument)
// is an InputError naming the store and the row.
template <class Parse>
auto parsed(const sql::Db& db, const std::string& row, Parse parse) {
  try {
    return parse();
  } catch (const std::invalid_argument& e) {
    throw InputError(sql::display_name(db.path()), row + ": " + e.what());
  }
}

// A job's status: none while pending (and where a store from before jobs has
// no row); other text must name a ParcelStatus.
std::optional<ParcelStatus> job_status(const sql::Db& db, const std::string& parcel_id, const std::string& text) {
  if (text.empty() || text == "pending") return std::nullopt;
  return parsed(db, "parcel " + parcel_id, [&] { return parcel_status_from(text); });
}

// A building's level of detail; a store from before LoDs were recorded holds 2.2 models only.
Lod building_lod(const sql::Db& db, const std::string& building_id, const std::string& text) {
  return parsed(db, "building " + building_id, [&] { return text.empty() ? Lod::Lod22 : lod_from(text); });
}

sql::Db open_store(const std::string& path) {
  if (sql::is_postgres_url(path)) {
    sql::Db db(path, true);
    if (!db.has_table("la_spatialunit") || !db.has_table("parcel_job"))
      throw InputError(sql::display_name(path), "not a Cadastre3D store (no la_spatialunit / parcel_job table)");
    return db;
  }
  if (!std::filesystem::exists(path)) throw InputError(path, "store not found");
  // Read-write but query-only where possible: the last connection to close
  // then folds the WAL away instead of leaving -wal / -shm files behind.
  sql::Db db;
  try {
    db = sql::Db(path, false);
    db.exec("PRAGMA query_only = 1");
  } catch (const InputError&) {
    db = sql::Db(path, true);
  }
  if (!db.has_table("la_spatialunit") || !db.has_table("parcel_job")) throw InputError(path, "not a Cadastre3D store");
  return db;
}

LocalFrame latest_frame(const sql::Db& db) {
  LocalFrame f;
  sql::Stmt q(db, "SELECT origin_x, origin_y, origin_z FROM run ORDER BY fid DESC LIMIT 1");
  if (q.step() && !q.is_null(0)) f.origin = Vec3(q.get_double(0), q.get_double(1), q.get_double(2));
  return f;
}

void read_crs(const sql::Db& db, BatchModel& m) {
  sql::Stmt q(db, db.postgres()
                      ? "SELECT g.srid, upper(s.auth_name), coalesce(s.srtext, 'undefined') FROM geometry_columns g "
                        "LEFT JOIN spatial_ref_sys s ON s.srid=g.srid WHERE g.f_table_schema = current_schema() "
                        "AND g.f_table_name='la_spatialunit'"
                      : "SELECT s.srs_id, s.organization, s.definition FROM gpkg_geometry_columns g "
                        "JOIN gpkg_spatial_ref_sys s ON s.srs_id=g.srs_id WHERE g.table_name='la_spatialunit'");
  if (!q.step()) return;
  if (q.get_text(1) == "EPSG") m.epsg = int(q.get_int(0));
  std::string def = q.get_text(2);
  if (def != "undefined") m.crs_wkt = def;
}

std::vector<Face> read_faces(const sql::Stmt& q, int col, const Vec3& origin) {
  std::size_t n;
  const std::uint8_t* b = q.blob(col, &n);
  return gpkg_read_faces(b, n, origin);
}

std::vector<Building> read_buildings(const sql::Db& db, std::int64_t su, const LocalFrame& frame) {
  // A store written before buildings recorded their LoD holds LoD 2.2 models only.
  const std::string lod = store_schema::has_column(db, "building", "lod") ? "lod, lod_note" : "'2.2', ''";
  sql::Stmt qb(db,
               "SELECT fid, geom, geom_kind, building_id, volume, eave_height, ridge_height, "
               "terrain_z, storeys, solid_valid, solid_problem, roof_dev_n, roof_dev_max, "
               "roof_dev_mean, roof_dev_std, roof_dev_rmse, wall_dev_n, wall_dev_max, wall_dev_mean, "
               "wall_dev_std, wall_dev_rmse, " + lod + " FROM building WHERE spatialunit_id=? ORDER BY building_index");
  const std::string shared = store_schema::has_column(db, "building_element", "sigma_shared") ? "sigma_shared" : "0";
  sql::Stmt qe(db,
               "SELECT geom, element_type, area, plan_area, slope_deg, azimuth_deg, sigma_area, "
               "support_points, rmse, wall_evidence, " + shared + " FROM building_element WHERE building_fid=? "
               "ORDER BY element_index");
  store_lods::Reader lods(db);
  std::vector<Building> out;
  qb.bind(su);
  while (qb.step()) {
    Building b;
    if (qb.get_text(2) == "solid") b.solid = read_faces(qb, 1, frame.origin);
    b.id = qb.get_text(3);
    b.volume = qb.get_double(4);
    b.eave_height = qb.get_double(5);
    b.ridge_height = qb.get_double(6);
    b.terrain_z = qb.get_double(7) - frame.origin.z();
    b.storeys = int(qb.get_int(8));
    b.solid_valid = qb.get_int(9) != 0;
    b.solid_problem = qb.get_text(10);
    Deviation* devs[2] = {&b.roof_deviation, &b.wall_deviation};
    for (int k = 0; k < 2; ++k) {
      int c = 11 + 5 * k;
      *devs[k] = {long(qb.get_int(c)), qb.get_double(c + 1), qb.get_double(c + 2),
                  qb.get_double(c + 3), qb.get_double(c + 4)};
    }
    b.lod = building_lod(db, b.id, qb.get_text(21));
    b.lod_note = qb.get_text(22);
    lods.read(qb.get_int(0), frame.origin, b);
    qe.bind(qb.get_int(0));
    while (qe.step()) {
      Element e;
      e.faces = read_faces(qe, 0, frame.origin);
      e.type = element_type_from(qe.get_text(1));
      e.area = qe.get_double(2);
      e.plan_area = qe.get_double(3);
      e.slope_deg = qe.get_double(4);
      e.azimuth_deg = qe.get_double(5);
      e.sigma_area = qe.get_double(6);
      e.support_points = int(qe.get_int(7));
      e.rmse = qe.get_double(8);
      e.evidence = evidence_from(qe.get_text(9));
      e.sigma_shared = qe.is_null(10) ? 0.0 : qe.get_double(10);
      b.elements.push_back(std::move(e));
    }
    qe.reset();
    out.push_back(std::move(b));
  }
  return out;
}

// At most this many ids bound in one query: well under SQLite's (32766) and
// libpq's (65535) limits on bound parameters; a page of parcels is one query.
constexpr size_t kIdsPerQuery = 1000;

// Reads in one snapshot: a parcel's row and its buildings' rows agree while
// another writer rewrites it (PostgreSQL: REPEATABLE READ; SQLite: a deferred
// read transaction, which holds no lock a writer waits on in WAL mode).
class ReadSnapshot {
 public:
  explicit ReadSnapshot(sql::Db& db) : db_(db) {
    db_.exec(db_.postgres() ? "BEGIN ISOLATION LEVEL REPEATABLE READ READ ONLY" : "BEGIN");
  }
  ~ReadSnapshot() {
    try {
      db_.exec("COMMIT");
    } catch (const std::exception&) {  // nothing was written: nothing to lose
    }
  }
  ReadSnapshot(const ReadSnapshot&) = delete;
  ReadSnapshot& operator=(const ReadSnapshot&) = delete;

 private:
  sql::Db& db_;
};

// " WHERE su.parcel_id IN (?,...)" with n placeholders.
std::string id_filter(size_t n) {
  std::string w = " WHERE su.parcel_id IN (";
  for (size_t k = 0; k < n; ++k) w += k ? ",?" : "?";
  return w + ")";
}

// Calls read(filter, ids) once for the whole store (ids null: no filter) or
// once per piece of at most kIdsPerQuery ids.
template <class Read>
void by_pieces(const std::vector<std::string>* ids, Read read) {
  if (!ids) return read(std::string(), std::vector<std::string>());
  for (size_t at = 0; at < ids->size(); at += kIdsPerQuery) {
    const auto from = ids->begin() + long(at), to = ids->begin() + long(std::min(at + kIdsPerQuery, ids->size()));
    read(id_filter(size_t(to - from)), std::vector<std::string>(from, to));
  }
}

// Positions in `got` in the order of `ids` (ids the store lacks left out).
std::vector<size_t> order_of(const std::vector<std::string>& ids, const std::vector<std::string>& got) {
  std::unordered_map<std::string, std::vector<size_t>> at;
  for (size_t i = 0; i < got.size(); ++i) at[got[i]].push_back(i);
  std::vector<size_t> out;
  for (const std::string& id : ids) {
    auto it = at.find(id);
    if (it == at.end()) continue;
    out.insert(out.end(), it->second.begin(), it->second.end());
    at.erase(it);  // an id asked twice comes once
  }
  return out;
}

template <class T>
std::vector<T> permuted(std::vector<T>& v, const std::vector<size_t>& order) {
  std::vector<T> out;
  out.reserve(order.size());
  for (size_t i : order) out.push_back(std::move(v[i]));
  return out;
}

// Appends the parcels the query with this filter gives (ids bound in order).
void read_parcels(const sql::Db& db, const std::string& filter, const std::vector<std::string>& ids, BatchModel& m) {
  // The layer's own name of the right; a store written before kept it in rrr_type.
  const std::string right =
      store_schema::has_column(db, "la_rrr", "local_type") ? "coalesce(r.local_type, r.rrr_type)" : "r.rrr_type";
  sql::Stmt q(db,
              "SELECT su.fid, su.geom, su.parcel_id, su.layer_index, su.official_area, "
              "su.repair_note, " + right + ", j.status, j.reason, j.roof_points, j.wall_points, "
              "j.timings FROM la_spatialunit su "
              "LEFT JOIN la_rrr r ON r.baunit_id = su.baunit_id "
              "LEFT JOIN parcel_job j ON j.parcel_id = su.parcel_id" + filter +
              " ORDER BY su.layer_index, su.parcel_id");
  for (const std::string& id : ids) q.bind(id);
  while (q.step()) {
    Parcel p;
    std::size_t n;
    const std::uint8_t* b = q.blob(1, &n);
    p.shape = gpkg_read_multipolygon(b, n);
    p.id = q.get_text(2);
    p.index = int(q.get_int(3));
    p.official_area = q.get_double(4);
    p.repair_note = q.get_text(5);
    p.right_type = q.get_text(6);
    ParcelResult r;
    r.parcel_index = p.index;
    r.parcel_id = p.id;
    r.status = job_status(db, p.id, q.get_text(7)).value_or(ParcelStatus::Empty);  // rewritten now: empty till done
    r.reason = q.get_text(8);
    r.roof_points = long(q.get_int(9));
    r.wall_points = long(q.get_int(10));
    r.timings = parse_timings(q.get_text(11));
    r.buildings = read_buildings(db, q.get_int(0), m.frame);
    m.parcels.push_back(std::move(p));
    m.results.push_back(std::move(r));
  }
}

BatchModel read_batch_model(const std::string& path, const std::vector<std::string>* ids) {
  sql::Db db = open_store(path);
  const ReadSnapshot snapshot(db);
  BatchModel m;
  m.frame = latest_frame(db);
  read_crs(db, m);
  try {
    by_pieces(ids, [&](const std::string& filter, const std::vector<std::string>& piece) {
      read_parcels(db, filter, piece, m);
    });
  } catch (const std::runtime_error& e) {
    if (dynamic_cast<const InputError*>(&e)) throw;
    throw InputError(path, e.what());  // malformed geometry blob
  }
  if (ids) {
    std::vector<std::string> got;
    for (const Parcel& p : m.parcels) got.push_back(p.id);
    const std::vector<size_t> order = order_of(*ids, got);
    m.parcels = permuted(m.parcels, order);
    m.results = permuted(m.results, order);
  }
  return m;
}

// Appends the valuations the query with this filter gives (ids bound in order).
void read_valuation_rows(const sql::Db& db, const std::string& filter, const std::vector<std::string>& ids,
                         std::vector<ParcelValuation>& out) {
  sql::Stmt q(db,
              "SELECT v.fid, u.parcel_id, v.currency, u.zone, u.quality, v.note, u.land_area, "
              "u.land_area_source, v.land_price_per_m2, v.land_value, v.building_cost, "
              "v.sigma_building_cost, v.age_years, v.depreciation_share, v.depreciation, "
              "v.building_value, v.sigma_building_value, v.njop, v.sigma_njop, v.tax_rate, "
              "v.njoptkp, v.taxable, v.tax, v.sigma_tax "
              "FROM la_spatialunit su JOIN vm_valuationunit u ON u.spatialunit_id = su.fid "
              "JOIN vm_valuation v ON v.valuationunit_id = u.fid" + filter +
              " ORDER BY su.layer_index, su.parcel_id");
  sql::Stmt qi(db,
               "SELECT building_id, element_index, element_type, quality, area, sigma_area, "
               "unit_cost, amount, sigma_amount, support_points, rmse FROM vm_cost_item "
               "WHERE valuation_id=? ORDER BY fid");
  for (const std::string& id : ids) q.bind(id);
  while (q.step()) {
    ParcelValuation v;
    v.parcel_id = q.get_text(1);
    v.currency = q.get_text(2);
    v.zone = q.get_text(3);
    v.quality = q.get_text(4);
    v.note = q.get_text(5);
    v.land_area = q.get_double(6);
    v.land_area_source = q.get_text(7);
    double* nums[] = {&v.land_price_per_m2, &v.land_value, &v.building_cost,
                      &v.sigma_building_cost, &v.age_years, &v.depreciation_share,
                      &v.depreciation, &v.building_value, &v.sigma_building_value, &v.njop,
                      &v.sigma_njop, &v.tax_rate, &v.njoptkp, &v.taxable, &v.tax, &v.sigma_tax};
    for (int k = 0; k < 16; ++k) *nums[k] = q.get_double(8 + k);
    qi.bind(q.get_int(0));
    while (qi.step()) {
      CostItem c;
      c.building_id = qi.get_text(0);
      c.element_index = qi.is_null(1) ? -1 : int(qi.get_int(1));
      c.element_type = qi.get_text(2);
      c.quality = qi.get_text(3);
      c.area = qi.get_double(4);
      c.sigma_area = qi.get_double(5);
      c.unit_cost = qi.get_double(6);
      c.amount = qi.get_double(7);
      c.sigma_amount = qi.get_double(8);
      c.support_points = int(qi.get_int(9));
      c.rmse = qi.get_double(10);
      v.items.push_back(std::move(c));
    }
    qi.reset();
    out.push_back(std::move(v));
  }
}

std::vector<ParcelValuation> read_valuations(const std::string& path, const std::vector<std::string>* ids) {
  sql::Db db = open_store(path);
  const ReadSnapshot snapshot(db);
  std::vector<ParcelValuation> out;
  by_pieces(ids, [&](const std::string& filter, const std::vector<std::string>& piece) {
    read_valuation_rows(db, filter, piece, out);
  });
  if (!ids) return out;
  std::vector<std::string> got;
  for (const ParcelValuation& v : out) got.push_back(v.parcel_id);
  return permuted(out, order_of(*ids, got));
}

}  // namespace

bool is_database_url(const std::string& loc) { return sql::is_postgres_url(loc); }

bool store_exists(const std::string& loc) {
  if (is_database_url(loc)) return sql::Db(loc, true).has_table("parcel_job");
  if (!std::filesystem::exists(loc)) return false;
  // The schema is written in one transaction: a batch killed before it
  // commits leaves a file without a single table (empty, or a header only),
  // which holds nothing to keep.
  if (std::filesystem::file_size(loc) == 0) return false;
  try {
    const sql::Db db(loc, true);
    sql::Stmt tables(db, "SELECT count(*) FROM sqlite_master WHERE type = 'table'");
    return !tables.step() || tables.get_int(0) > 0;
  } catch (const InputError&) {
    throw InputError(loc, "not a GeoPackage or SQLite file; left as it is: choose another --store or --out");
  }
}

BatchModel load_batch_model(const std::string& path) { return read_batch_model(path, nullptr); }

BatchModel load_batch_model(const std::string& path, const std::vector<std::string>& parcel_ids) {
  return read_batch_model(path, &parcel_ids);
}

std::vector<ParcelValuation> load_valuations(const std::string& path) { return read_valuations(path, nullptr); }

std::vector<ParcelValuation> load_valuations(const std::string& path, const std::vector<std::string>& parcel_ids) {
  return read_valuations(path, &parcel_ids);
}

std::vector<JobRecord> load_jobs(const std::string& path) {
  sql::Db db = open_store(path);
  sql::Stmt q(db,
              "SELECT parcel_id, layer_index, status, reason, inputs_key, updated, run_id "
              "FROM parcel_job ORDER BY layer_index, parcel_id");
  std::vector<JobRecord> out;
  while (q.step())
    out.push_back({q.get_text(0), int(q.get_int(1)), job_status(db, q.get_text(0), q.get_text(2)), q.get_text(3),
                   q.get_text(4), q.get_text(5), q.get_int(6)});
  return out;
}

std::vector<RunRecord> load_runs(const std::string& path) {
  sql::Db db = open_store(path);
  const std::string shard = store_schema::has_column(db, "run", "shard") ? "shard" : "NULL";
  const std::string suspect = store_schema::has_column(db, "run", "parcels_suspect") ? "parcels_suspect" : "0";
  sql::Stmt q(db,
              "SELECT fid, tool_version, parameters, started, finished, crs_epsg, origin_x, "
              "origin_y, origin_z, parcels_ok, parcels_empty, parcels_failed, " + shard + ", " + suspect +
              " FROM run ORDER BY fid");
  // A store from before roles has none: "" (merge judges those by the file's name).
  const std::string role = store_schema::has_column(db, "run_input", "role") ? "role" : "NULL";
  sql::Stmt qi(db, "SELECT path, sha256, bytes, " + role + " FROM run_input WHERE run_id=? ORDER BY fid");
  std::vector<RunRecord> out;
  while (q.step()) {
    RunRecord r;
    r.id = q.get_int(0);
    r.tool_version = q.get_text(1);
    r.parameters = q.get_text(2);
    r.started = q.get_text(3);
    r.finished = q.get_text(4);
    r.epsg = int(q.get_int(5));
    r.origin = Vec3(q.get_double(6), q.get_double(7), q.get_double(8));
    r.parcels_ok = int(q.get_int(9));
    r.parcels_empty = int(q.get_int(10));
    r.parcels_failed = int(q.get_int(11));
    r.shard = q.get_text(12);
    r.parcels_suspect = int(q.get_int(13));
    qi.bind(r.id);
    while (qi.step()) r.inputs.push_back({qi.get_text(0), qi.get_text(1), qi.get_int(2), qi.get_text(3)});
    qi.reset();
    out.push_back(std::move(r));
  }
  return out;
}

}  // namespace c3d
