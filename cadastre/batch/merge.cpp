#include "cadastre/batch/merge.h"

#include "cadastre/batch/building_meshes.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <memory>
#include <set>

#include "cadastre/batch/batch.h"
#include "cadastre/batch/out_dir.h"
#include "cadastre/batch/run_fit.h"
#include "cadastre/batch/shard.h"
#include "cadastre/batch/tiles.h"
#include "cadastre/store/gpkg_rtree.h"
#include "cadastre/store/sql_db.h"
#include "cadastre/store/store.h"
#include "core/error.h"

namespace c3d {
namespace {

// What must agree between the shards of one run, read from a shard's store.
struct ShardStore {
  std::string path;
  Shard shard;
  RunRecord run;  // the latest
  int srs_id = 0;
  std::string srs_org, srs_definition;
};

ShardStore read_shard_store(const std::string& path) {
  const std::vector<RunRecord> runs = load_runs(path);  // InputError when no store
  if (runs.empty() || runs.back().shard.empty())
    throw InputError(path, "is not a shard's store (its run has no --shard K/N)");
  ShardStore s{path, parse_shard(runs.back().shard), runs.back(), 0, "", ""};
  sql::Db db(path, true);
  sql::Stmt q(db,
              "SELECT s.srs_id, s.organization, s.definition FROM gpkg_geometry_columns g "
              "JOIN gpkg_spatial_ref_sys s ON s.srs_id=g.srs_id WHERE g.table_name='la_spatialunit'");
  if (q.step()) s.srs_id = int(q.get_int(0)), s.srs_org = q.get_text(1), s.srs_definition = q.get_text(2);
  return s;
}

// A shard's own point files (--cloud, --walls), by their role; a record from
// before roles (run_input without a role) by the file's name.
bool is_point_input(const InputFile& f) {
  if (f.role.empty()) return is_point_file(f.path);
  return f.role == input_role::kCloud || f.role == input_role::kWalls;
}

// The files every shard reads alike (layer, DTM, classifier): a shard reads
// only the point files within reach of its parcels, so those differ; each
// parcel's key holds its own (checked when merge is given the inputs).
std::vector<std::string> shared_input_hashes(const RunRecord& r) {
  std::vector<std::string> h;
  for (const auto& f : r.inputs)
    if (!is_point_input(f)) h.push_back(f.sha256);
  return h;
}

// The merged run's inputs with their roles: every shard's point files, once
// each, in the order met, then the shared files.
std::vector<InputFile> merged_inputs(const std::vector<ShardStore>& stores) {
  std::vector<InputFile> out;
  std::set<std::string> seen;
  for (const ShardStore& s : stores)
    for (const InputFile& f : s.run.inputs)
      if (is_point_input(f) && seen.insert(f.sha256).second) out.push_back(f);
  for (const InputFile& f : stores.front().run.inputs)
    if (!is_point_input(f)) out.push_back(f);
  return out;
}

// Refuses shards that read one point file as different contents: each
// records the point files within its reach, so a file two shards read must
// have one SHA-256 in both (a cloud regenerated between shards).
void check_same_point_files(const std::vector<ShardStore>& stores) {
  std::map<std::string, std::pair<std::string, std::string>> read;  // path -> (SHA-256, the store that read it)
  for (const ShardStore& s : stores)
    for (const InputFile& f : s.run.inputs) {
      if (!is_point_input(f)) continue;
      const auto [at, first] = read.emplace(f.path, std::make_pair(f.sha256, s.path));
      if (!first && at->second.first != f.sha256)
        throw InputError(s.path, "read " + f.path + " with SHA-256 " + f.sha256.substr(0, 12) + "..., " +
                                     at->second.second + " read another file under that name (" +
                                     at->second.first.substr(0, 12) + "...): shards of different clouds");
    }
}

// Refuses stores that are not shards of the same run, or a shard given twice.
void check_same_run(const std::vector<ShardStore>& stores) {
  const ShardStore& a = stores.front();
  check_same_point_files(stores);
  std::map<int, std::string> seen;
  for (const ShardStore& s : stores) {
    if (s.shard.n != a.shard.n)
      throw InputError(s.path, "is shard " + to_string(s.shard) + ", " + a.path + " is of " +
                                   std::to_string(a.shard.n) + " shards");
    if (!parameters_difference(s.run.parameters, a.run.parameters).empty())
      throw InputError(s.path, "was run with other parameters than " + a.path);
    if (shared_input_hashes(s.run) != shared_input_hashes(a.run))
      throw InputError(s.path, "was run on other inputs than " + a.path);
    if (s.srs_id != a.srs_id || s.srs_definition != a.srs_definition)
      throw InputError(s.path, "has another CRS than " + a.path);
    if (!seen.emplace(s.shard.k, s.path).second)
      throw InputError(s.path, "is shard " + to_string(s.shard) + ", given twice (also " + seen[s.shard.k] + ")");
  }
}

// What the merge compares of a parcel found in two stores: status, reason,
// key, element areas and the valuation.
std::string parcel_content(const sql::Db& db, const std::string& schema, const std::string& parcel_id) {
  const std::string s = schema + ".";
  sql::Stmt q(db,
              "SELECT j.status || '|' || coalesce(j.reason,'') || '|' || coalesce(j.inputs_key,'') || '|' || "
              "coalesce((SELECT group_concat(a, ',') FROM (SELECT printf('%.6f', e.area) AS a FROM " + s +
              "building_element e JOIN " + s + "building b ON e.building_fid=b.fid JOIN " + s +
              "la_spatialunit su ON b.spatialunit_id=su.fid WHERE su.parcel_id=j.parcel_id "
              "ORDER BY b.building_index, e.element_index)),'') || '|' || "
              "coalesce((SELECT printf('%.6f|%.6f', v.njop, v.tax) FROM " + s + "vm_valuation v JOIN " + s +
              "vm_valuationunit u ON v.valuationunit_id=u.fid WHERE u.parcel_id=j.parcel_id),'') "
              "FROM " + s + "parcel_job j WHERE j.parcel_id=?");
  q.bind(parcel_id);
  return q.step() ? q.get_text(0) : "";
}

// A parcel already merged that this shard holds too: the same content is
// taken once (the merged copy goes, the shard's comes), other content refused.
void drop_overlaps(sql::Db& db, const std::string& path, std::map<std::string, std::string>& origin) {
  std::vector<std::string> both;
  {
    sql::Stmt q(db, "SELECT parcel_id FROM shard.parcel_job INTERSECT SELECT parcel_id FROM main.parcel_job");
    while (q.step()) both.push_back(q.get_text(0));
  }
  sql::Stmt del_unit(db, "DELETE FROM main.la_baunit WHERE parcel_id=?");  // cascades to its rows
  sql::Stmt del_job(db, "DELETE FROM main.parcel_job WHERE parcel_id=?");
  for (const std::string& id : both) {
    if (parcel_content(db, "shard", id) != parcel_content(db, "main", id))
      throw InputError(path, "parcel " + id + " differs from the same parcel in " + origin[id]);
    del_unit.bind(id).run();
    del_job.bind(id).run();
  }
}

struct Column {
  std::string name, type;
};

std::vector<Column> columns_of(const sql::Db& db, const std::string& schema, const std::string& table) {
  sql::Stmt q(db, "SELECT name, type FROM " + schema + ".pragma_table_info(?) ORDER BY cid");
  q.bind(table);
  std::vector<Column> out;
  while (q.step()) out.push_back({q.get_text(0), q.get_text(1)});
  return out;
}

// The tables that hold parcels' rows: all but the GeoPackage's own, the
// spatial indexes (their triggers refill them), the run record and the styles.
std::vector<std::string> parcel_tables(const sql::Db& db) {
  sql::Stmt q(db,
              "SELECT name FROM shard.sqlite_master WHERE type='table' AND name NOT LIKE 'gpkg_%' "
              "AND name NOT LIKE 'rtree_%' AND name NOT LIKE 'sqlite_%' "
              "AND name NOT IN ('run','run_input','layer_styles') ORDER BY name");
  std::vector<std::string> out;
  while (q.step()) out.push_back(q.get_text(0));
  return out;
}

// Copies every row of the attached shard into main: each table's fid moved
// past main's rows, references moved with the table they point at, run ids
// set to the merged run's.
void copy_rows(sql::Db& db, std::int64_t run_id) {
  const std::vector<std::string> tables = parcel_tables(db);
  std::map<std::string, std::int64_t> offset;
  for (const std::string& t : tables) {
    sql::Stmt q(db, "SELECT coalesce(max(fid), 0) FROM main." + t);
    offset[t] = q.step() ? q.get_int(0) : 0;
  }
  for (const std::string& t : tables) {
    std::map<std::string, std::string> refers;  // column -> table
    {
      sql::Stmt q(db, "SELECT \"from\", \"table\" FROM shard.pragma_foreign_key_list(?)");
      q.bind(t);
      while (q.step()) refers[q.get_text(0)] = q.get_text(1);
    }
    std::set<std::string> have;
    for (const Column& c : columns_of(db, "main", t)) have.insert(c.name);
    std::string names, values;
    for (const Column& c : columns_of(db, "shard", t)) {
      // A column main lacks (the parcel layer's own fields): added as the shard has it.
      if (!have.count(c.name)) db.exec("ALTER TABLE main." + t + " ADD COLUMN \"" + c.name + "\" " + c.type);
      const std::string col = "\"" + c.name + "\"";
      std::string v = col;
      if (c.name == "fid") v = col + " + " + std::to_string(offset[t]);
      else if (refers.count(c.name) && refers[c.name] == "run") v = "CASE WHEN " + col + " IS NULL THEN NULL ELSE " + std::to_string(run_id) + " END";
      else if (refers.count(c.name) && offset.count(refers[c.name])) v = col + " + " + std::to_string(offset[refers[c.name]]);
      names += (names.empty() ? "" : ",") + col;
      values += (values.empty() ? "" : ",") + v;
    }
    db.exec("INSERT INTO main." + t + " (" + names + ") SELECT " + values + " FROM shard." + t + " ORDER BY fid");
  }
}

// Attaches one shard's store, copies its parcels into main, detaches it.
void merge_one(sql::Db& db, const ShardStore& s, std::int64_t run_id, std::map<std::string, std::string>& origin) {
  sql::Stmt attach(db, "ATTACH DATABASE ? AS shard");
  attach.bind(s.path).run();
  {
    sql::Transaction tx(db);
    db.exec("PRAGMA defer_foreign_keys = ON");  // rows come table by table, checked at commit
    drop_overlaps(db, s.path, origin);
    copy_rows(db, run_id);
    tx.commit();
  }
  sql::Stmt q(db, "SELECT parcel_id FROM shard.parcel_job");
  while (q.step()) origin[q.get_text(0)] = s.path;
  q.reset();
  db.exec("DETACH DATABASE shard");
}

}  // namespace

MergeSummary merge_stores(const std::vector<std::string>& shards, const std::string& out_store) {
  if (shards.empty()) throw InputError("merge", "no shard store given");
  if (std::filesystem::exists(out_store)) throw InputError(out_store, "exists already; merge writes a new store");
  std::vector<ShardStore> stores;
  for (const std::string& p : shards) stores.push_back(read_shard_store(p));
  check_same_run(stores);
  std::sort(stores.begin(), stores.end(), [](const ShardStore& a, const ShardStore& b) { return a.shard.k < b.shard.k; });
  const ShardStore& first = stores.front();
  MergeSummary sum;
  sum.shard_count = first.shard.n;
  sum.parameters = first.run.parameters;
  for (int k = 1, i = 0; k <= sum.shard_count; ++k)
    if (i < int(stores.size()) && stores[size_t(i)].shard.k == k) ++i;
    else sum.missing_shards.push_back(k);

  Store store;  // the merged run record: the shards' parameters, inputs and frame
  const bool epsg = first.srs_org == "EPSG";
  const std::string wkt = first.srs_definition == "undefined" ? "" : first.srs_definition;
  store.open(out_store, wkt, epsg ? first.srs_id : 0);
  LocalFrame frame;
  frame.origin = first.run.origin;
  const std::int64_t run_id = store.begin_run(first.run.parameters, merged_inputs(stores), frame);
  {
    sql::Db db(out_store, false);
    gpkg_rtree::register_functions(db);  // the spatial index triggers call them
    db.exec("PRAGMA foreign_keys = ON");
    std::map<std::string, std::string> origin;  // parcel id -> the store it came from
    for (const ShardStore& s : stores) merge_one(db, s, run_id, origin);
    sql::Stmt q(db, "SELECT parcel_id FROM parcel_job WHERE status='pending' ORDER BY layer_index");
    while (q.step()) sum.pending.push_back(q.get_text(0));
    sql::Stmt n(db, "SELECT count(*) FROM la_spatialunit");
    sum.parcels = n.step() ? size_t(n.get_int(0)) : 0;
  }
  store.end_run(false);  // counts and extents; finished once the outputs are in place
  store.close();
  return sum;
}

namespace {

// The outputs a batch writes, from the store as it holds the shards' parcels;
// the whole-run fit from the batch's inputs when given and every shard is in.
void write_merged_outputs(MergedRun& m, const std::string& out_dir, const std::vector<std::string>& formats,
                          const OutputProgress& progress, const RunInputs* inputs, const LoadedInputs* in) {
  BatchReport report;  // the counts as the store holds them
  for (const JobRecord& j : load_jobs(m.store))
    if (j.status) ++m.status_counts[size_t(*j.status)];
  for (size_t k = 0; k < 4; ++k) report.held_by_status[k] = m.status_counts[k], report.parcels += m.status_counts[k];
  report.reconstructed = report.held = report.parcels;
  report.failed = m.status_counts[size_t(ParcelStatus::Failed)];
  report.suspect = m.status_counts[size_t(ParcelStatus::Suspect)];
  if (!inputs)
    report.fit_missing = "merged without the batch's inputs (give merge the batch's --cloud, --parcels, ... options)";
  else if (!m.merge.complete())
    report.fit_missing = "shards or parcels are missing";
  else
    store_fit(*in, inputs->cfg, m.store, report);
  m.fit_missing = report.fit_missing;
  m.written = write_outputs(report, m.store, out_dir, inputs ? inputs->cfg : default_config(), formats, progress);
}

}  // namespace

MergedRun merge_run(const std::vector<std::string>& shards, const std::string& out_dir,
                    const std::vector<std::string>& formats, bool overwrite, const OutputProgress& progress,
                    const RunInputs* inputs) {
  std::filesystem::create_directories(out_dir);
  const OutDirLock lock(out_dir);
  // The inputs checked before anything is written.
  const std::unique_ptr<LoadedInputs> in(inputs ? new LoadedInputs(load_run_inputs(*inputs, shards)) : nullptr);
  if (overwrite) remove_batch_outputs(out_dir);
  MergedRun m;
  m.store = (std::filesystem::path(out_dir) / "cadastre.gpkg").string();
  if (std::filesystem::exists(m.store)) throw InputError(m.store, "exists already; --overwrite replaces it");
  m.merge = merge_stores(shards, m.store);
  gather_mesh_files(shards, out_dir);
  write_merged_outputs(m, out_dir, formats, progress, inputs, in.get());
  if (m.merge.complete()) mark_run_finished(m.store);  // a finished run: every parcel and output in place
  return m;
}

MergedRun finish_shared_store(const std::string& store, const std::string& out_dir,
                              const std::vector<std::string>& formats, bool overwrite,
                              const OutputProgress& progress, const RunInputs* inputs) {
  std::filesystem::create_directories(out_dir);
  const OutDirLock lock(out_dir);
  if (overwrite) remove_batch_outputs(out_dir);
  MergedRun m;
  m.store = store;
  std::set<int> ran;  // the shards that began a run
  for (const RunRecord& r : load_runs(store))
    if (!r.shard.empty()) ran.insert(parse_shard(r.shard).k), m.merge.shard_count = parse_shard(r.shard).n;
  for (int k = 1; k <= m.merge.shard_count; ++k)
    if (!ran.count(k)) m.merge.missing_shards.push_back(k);
  for (const JobRecord& j : load_jobs(store))
    if (!j.status) m.merge.pending.push_back(j.parcel_id);
    else ++m.merge.parcels;
  const std::unique_ptr<LoadedInputs> in(inputs ? new LoadedInputs(load_run_inputs(*inputs, {store})) : nullptr);
  write_merged_outputs(m, out_dir, formats, progress, inputs, in.get());
  return m;
}

}  // namespace c3d
