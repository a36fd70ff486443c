// Shards of a batch (--shard K/N) and their merge (issue 37): the shards
// cover the layer once, a shard stores only its own parcels, and the merged
// shards equal one unsharded run: parcels, statuses, element areas, NJOP, tax,
// and, given the batch's inputs, the summary's whole-run fit.
#include <gdal_utils.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "cadastre/batch/merge.h"
#include "cadastre/batch/shard.h"
#include "cadastre/batch/store_sink.h"
#include "cadastre/store/store.h"
#include "core/error.h"
#include "tests/test_support.h"

using namespace c3d;
namespace fs = std::filesystem;

TEST(Shard, ParsesKOfNAndRefusesTheRest) {
  const Shard s = parse_shard("2/4");
  EXPECT_EQ(s.k, 2);
  EXPECT_EQ(s.n, 4);
  EXPECT_EQ(to_string(s), "2/4");
  EXPECT_EQ(to_string(Shard{}), "");
  for (const char* bad : {"0/3", "4/3", "3", "/3", "1/", "a/b", "1/3x", "-1/3", "1/0", ""})
    EXPECT_THROW(parse_shard(bad), InputError) << bad;
  try {  // K/N indeed, but more shards than an int holds: said so, not "not K/N"
    parse_shard("1/9999999999");
    ADD_FAILURE() << "parsed";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("more shards than 999999999"), std::string::npos) << e.what();
  }
  // A bad --shard is a usage error, exit code 2, as the other options' are.
  std::string out;
  EXPECT_EQ(test::run_cli("batch --cloud c.las --parcels p.gpkg --out o --shard 0/3", &out), 2) << out;
  EXPECT_NE(out.find("'0/3' is not K/N"), std::string::npos) << out;
}

TEST(Shard, PartsCoverTheLayerOnceAndAreCompact) {
  std::vector<Parcel> layer;  // a 12 x 10 grid of 10 m parcels
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 12; ++x) {
      Parcel p;
      p.index = int(layer.size());
      p.shape = {{{Vec2(10 * x, 10 * y), Vec2(10 * x + 10, 10 * y), Vec2(10 * x + 10, 10 * y + 10),
                   Vec2(10 * x, 10 * y + 10)}, {}}};
      layer.push_back(p);
    }
  EXPECT_EQ(shard_parcels(layer, {}).size(), layer.size());
  EXPECT_EQ(shard_parcels(layer, {1, 1}).size(), layer.size());
  std::vector<int> seen(layer.size(), 0);
  for (int k = 1; k <= 4; ++k) {
    const std::vector<size_t> part = shard_parcels(layer, {k, 4});
    EXPECT_EQ(part.size(), 30u);
    EXPECT_TRUE(std::is_sorted(part.begin(), part.end()));
    double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
    for (size_t i : part) {
      ++seen[i];
      const Vec2 c = layer[i].shape[0].outer[0];
      x0 = std::min(x0, c.x()), x1 = std::max(x1, c.x()), y0 = std::min(y0, c.y()), y1 = std::max(y1, c.y());
    }
    // A compact area: its box holds at most twice its parcels (stripes would hold the whole grid).
    EXPECT_LE((x1 - x0 + 10) * (y1 - y0 + 10) / 100, 60) << "shard " << k;
  }
  for (int n : seen) EXPECT_EQ(n, 1);
}

namespace {

const test::SampleTown& sample_town();

// Runs the sample town (one shard of it, or all) into a fresh store (or
// `store`), from its own inputs or `inputs`.
std::string run_town(const std::string& name, Shard shard = {}, BatchReport* report = nullptr,
                     std::string store = "", const BatchInputs* inputs = nullptr, bool resume = false) {
  if (store.empty()) store = test::temp_dir(name) + "/cadastre.gpkg";
  StoreSink sink(store);
  BatchSettings settings;
  settings.jobs = 2;
  settings.shard = shard;
  settings.resume = resume;
  const BatchReport r = run_batch(inputs ? *inputs : sample_town().inputs, default_config(), sink, settings);
  if (report) *report = r;
  return store;
}

std::vector<std::string> roles_of(const RunRecord& run) {
  std::vector<std::string> roles;
  for (const InputFile& f : run.inputs) roles.push_back(f.role);
  return roles;
}

std::set<std::string> stored_ids(const std::string& store) {
  std::set<std::string> ids;
  for (const Parcel& p : load_batch_model(store).parcels) ids.insert(p.id);
  for (const JobRecord& j : load_jobs(store)) ids.insert(j.parcel_id);
  return ids;
}

// The equality of issue 37: parcels, statuses, element areas (1e-6 m2), NJOP and tax (1e-6).
void expect_equal_stores(const std::string& want_store, const std::string& got_store) {
  const BatchModel want = load_batch_model(want_store), got = load_batch_model(got_store);
  ASSERT_EQ(want.parcels.size(), got.parcels.size());
  for (size_t i = 0; i < want.parcels.size(); ++i) {
    const ParcelResult &a = want.results[i], &b = got.results[i];
    ASSERT_EQ(want.parcels[i].id, got.parcels[i].id);
    EXPECT_EQ(a.status, b.status) << a.parcel_id;
    ASSERT_EQ(a.buildings.size(), b.buildings.size()) << a.parcel_id;
    for (size_t k = 0; k < a.buildings.size(); ++k) {
      ASSERT_EQ(a.buildings[k].elements.size(), b.buildings[k].elements.size()) << a.parcel_id;
      for (size_t e = 0; e < a.buildings[k].elements.size(); ++e)
        EXPECT_NEAR(a.buildings[k].elements[e].area, b.buildings[k].elements[e].area, 1e-6) << a.parcel_id;
    }
  }
  const auto va = load_valuations(want_store), vb = load_valuations(got_store);
  ASSERT_EQ(va.size(), vb.size());
  for (size_t i = 0; i < va.size(); ++i) {
    EXPECT_EQ(va[i].parcel_id, vb[i].parcel_id);
    EXPECT_NEAR(va[i].njop, vb[i].njop, 1e-6) << va[i].parcel_id;
    EXPECT_NEAR(va[i].tax, vb[i].tax, 1e-6) << va[i].parcel_id;
  }
}

// The unsharded run's whole-run fit, under the keys summary.json gives it
// (JSON numbers keep doubles exactly).
nlohmann::json whole_run_fit(const BatchReport& r) {
  nlohmann::json j;
  for (const auto& [key, d] : {std::pair<std::string, Deviation>{"any_model_roof_deviation", r.any_model_roof},
                               {"any_model_wall_deviation", r.any_model_wall}})
    j[key] = {{"n", d.n}, {"rmse", d.rmse}, {"mean", d.mean}, {"max", d.max}};
  for (const auto& [key, f] :
       {std::pair<std::string, RulerFigures>{"roof_ruler", r.roof_ruler}, {"wall_ruler", r.wall_ruler}})
    j[key] = {{"n", f.n}, {"median", f.median}, {"p95", f.p95}, {"rmse", f.rmse}};
  j["wall_points_measured_share"] = r.wall_points_measured;
  return j;
}

struct Shards {
  test::SampleTown town;
  std::string full;
  std::vector<std::string> stores;  // shard 1..3 of 3
  nlohmann::json whole;             // the unsharded run's fit (whole_run_fit)
};

// The town, its unsharded run and its three shards, made once for every
// process of a ctest run (test::shared_run); tests read them or copy them.
const Shards& three_shards() {
  static const Shards s = [] {
    Shards r;
    const auto files_in = [&r](const std::string& dir) {
      r.town = test::sample_town_files(dir + "/town");
      r.full = dir + "/full.gpkg";
      r.stores.clear();
      for (int k = 1; k <= 3; ++k) r.stores.push_back(dir + "/shard" + std::to_string(k) + ".gpkg");
    };
    const std::string dir = test::shared_run("shards_of_town", [&](const std::string& d) {
      std::string log;
      if (test::run_cli("sample --out " + d + "/town --parcels 24 --seed 3", &log) != 0) {
        ADD_FAILURE() << log;
        return false;
      }
      files_in(d);
      BatchReport whole;
      run_town("", {}, &whole, r.full, &r.town.inputs);
      for (int k = 1; k <= 3; ++k) run_town("", {k, 3}, nullptr, r.stores[size_t(k - 1)], &r.town.inputs);
      std::ofstream(d + "/whole_fit.json") << whole_run_fit(whole).dump();
      return true;
    });
    files_in(dir);
    std::ifstream f(dir + "/whole_fit.json");
    r.whole = nlohmann::json::parse(f, nullptr, false);
    return r;
  }();
  return s;
}

const test::SampleTown& sample_town() { return three_shards().town; }

}  // namespace

TEST(ShardMerge, AShardStoresOnlyItsOwnParcels) {
  const Shards& s = three_shards();
  const std::vector<Parcel> layer = load_batch_model(s.full).parcels;
  ASSERT_EQ(layer.size(), 24u);
  std::set<std::string> all;
  for (int k = 1; k <= 3; ++k) {
    std::set<std::string> own;
    for (size_t i : shard_parcels(layer, {k, 3})) own.insert(layer[i].id);
    const std::set<std::string> stored = stored_ids(s.stores[size_t(k - 1)]);
    EXPECT_EQ(stored, own) << "shard " << k;  // none of another shard's, not even pending
    all.insert(stored.begin(), stored.end());
    const auto runs = load_runs(s.stores[size_t(k - 1)]);
    ASSERT_EQ(runs.size(), 1u);
    EXPECT_EQ(runs[0].shard, std::to_string(k) + "/3");
  }
  EXPECT_EQ(all.size(), 24u);
  EXPECT_EQ(load_runs(s.full)[0].shard, "");
}

TEST(ShardMerge, MergedShardsEqualTheUnshardedRun) {
  const Shards& s = three_shards();
  const std::string merged = test::temp_dir("merged") + "/cadastre.gpkg";
  const MergeSummary sum = merge_stores({s.stores[2], s.stores[0], s.stores[1]}, merged);  // any order
  EXPECT_TRUE(sum.complete());
  EXPECT_EQ(sum.parcels, 24u);
  expect_equal_stores(s.full, merged);
  // The merged run is recorded as the unsharded one: its parameters and inputs.
  const RunRecord want = load_runs(s.full).back(), got = load_runs(merged).back();
  EXPECT_EQ(got.parameters, want.parameters);
  ASSERT_EQ(got.inputs.size(), want.inputs.size());
  EXPECT_EQ(roles_of(want), (std::vector<std::string>{"cloud", "parcels", "dtm"}));
  for (size_t i = 0; i < want.inputs.size(); ++i) {
    EXPECT_EQ(got.inputs[i].sha256, want.inputs[i].sha256);
    EXPECT_EQ(got.inputs[i].role, want.inputs[i].role);  // the merged record keeps the roles
  }
  EXPECT_EQ(got.shard, "");
  EXPECT_EQ(got.parcels_ok + got.parcels_empty + got.parcels_failed, want.parcels_ok + want.parcels_empty + want.parcels_failed);
  EXPECT_EQ(test::sql_number(merged, "SELECT count(*) - count(DISTINCT parcel_id) FROM la_spatialunit"), 0);
  EXPECT_EQ(test::sql_number(merged, "SELECT count(*) FROM building_element"),
            test::sql_number(s.full, "SELECT count(*) FROM building_element"));
  EXPECT_EQ(test::sql_number(merged, "SELECT count(*) FROM rtree_building_geom"),
            test::sql_number(s.full, "SELECT count(*) FROM building"));  // the spatial index follows
}

TEST(ShardMerge, RefusesWhatIsNotOneRunsShards) {
  const Shards& s = three_shards();
  const std::string dir = test::temp_dir("refused");
  auto refused = [&](const std::vector<std::string>& stores, const std::string& names) {
    try {
      merge_stores(stores, dir + "/m" + std::to_string(fs::exists(dir + "/m0")) + ".gpkg");
      ADD_FAILURE() << "merged, expected a refusal naming " << names;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(names), std::string::npos) << e.what();
    }
  };
  refused({s.stores[0], s.stores[0]}, "given twice");
  refused({s.stores[0], s.full}, s.full + ": is not a shard's store");
  // Other parameters.
  const std::string other = dir + "/other.gpkg";
  fs::copy_file(s.stores[1], other);
  test::sql_exec(other, "UPDATE run SET parameters = replace(parameters, '\"rate\":0.001', '\"rate\":0.002')");
  refused({s.stores[0], other}, other + ": was run with other parameters");
  // A shard of another cloud under the same name (issue 49): merged without
  // the inputs, it mixed two clouds' models.
  const std::string regenerated = dir + "/regenerated.gpkg";
  fs::copy_file(s.stores[1], regenerated);
  test::sql_exec(regenerated, "UPDATE run_input SET sha256 = 'f00d' || substr(sha256, 5) WHERE role = 'cloud'");
  refused({s.stores[0], regenerated}, regenerated + ": read ");
  refused({s.stores[0], regenerated}, "shards of different clouds");
  // A parcel of shard 1 posing as shard 2 with other content; with the same content it is taken once.
  const std::string twin = dir + "/twin.gpkg";
  fs::copy_file(s.stores[0], twin);
  test::sql_exec(twin, "UPDATE run SET shard = '2/3'");
  const std::string same = dir + "/same.gpkg";
  const MergeSummary sum = merge_stores({s.stores[0], twin, s.stores[2]}, same);
  EXPECT_EQ(sum.parcels, 16u);
  EXPECT_EQ(test::sql_number(same, "SELECT count(*) FROM parcel_job"), 16);
  test::sql_exec(twin, "UPDATE vm_valuation SET njop = njop + 1 WHERE fid = (SELECT max(fid) FROM vm_valuation)");
  refused({s.stores[0], twin}, twin + ": parcel ");
}

namespace {

// The sample town's parcel layer as a CSV file (geometry as WKT): a name a
// point file could have. With CRLF the same parcels in other bytes: another layer.
std::string layer_as_csv(const std::string& path, bool crlf) {
  GDALAllRegister();
  GDALDatasetH src = GDALOpenEx(sample_town().inputs.parcels.c_str(), GDAL_OF_VECTOR, nullptr, nullptr, nullptr);
  EXPECT_NE(src, nullptr);
  const char* args[] = {"-f",  "CSV", "-lco", "GEOMETRY=AS_WKT",
                        "-lco", crlf ? "LINEFORMAT=CRLF" : "LINEFORMAT=LF", nullptr};
  GDALVectorTranslateOptions* o = GDALVectorTranslateOptionsNew(const_cast<char**>(args), nullptr);
  GDALDatasetH out = GDALVectorTranslate(path.c_str(), nullptr, 1, &src, o, nullptr);
  EXPECT_NE(out, nullptr) << path;
  GDALClose(out);
  GDALVectorTranslateOptionsFree(o);
  GDALClose(src);
  return path;
}

}  // namespace

// The run record says which file was the parcel layer, whatever its name: two
// shards given different layers are no one run's shards, the same layer merges.
TEST(ShardMerge, RefusesShardsGivenOtherParcelLayersWhateverTheirNames) {
  const std::string dir = test::temp_dir("csv_layers");
  BatchInputs a = sample_town().inputs, b = a;
  a.parcels = layer_as_csv(dir + "/parcels_a.csv", false);
  b.parcels = layer_as_csv(dir + "/parcels_b.csv", true);
  const std::string a1 = run_town("a1", {1, 2}, nullptr, "", &a), a2 = run_town("a2", {2, 2}, nullptr, "", &a),
                    b2 = run_town("b2", {2, 2}, nullptr, "", &b);
  EXPECT_EQ(roles_of(load_runs(b2).back()), (std::vector<std::string>{"cloud", "parcels", "dtm"}));
  try {
    merge_stores({a1, b2}, dir + "/refused.gpkg");
    ADD_FAILURE() << "merged shards given other parcel layers";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(b2 + ": was run on other inputs than " + a1), std::string::npos) << e.what();
  }
  const MergeSummary sum = merge_stores({a1, a2}, dir + "/merged.gpkg");
  EXPECT_TRUE(sum.complete());
  EXPECT_EQ(sum.parcels, 24u);
  const RunRecord merged = load_runs(dir + "/merged.gpkg").back();
  ASSERT_EQ(roles_of(merged), (std::vector<std::string>{"cloud", "parcels", "dtm"}));  // the layer once
  EXPECT_EQ(merged.inputs[1].path, a.parcels);
}

// Stores written before run_input had a role still merge (their point files
// known by name) and resume (the column added, the new run's roles in it).
TEST(ShardMerge, StoresFromBeforeInputRolesMergeAndResume) {
  const Shards& s = three_shards();
  const std::string dir = test::temp_dir("before_roles");
  std::vector<std::string> old;
  for (int k = 1; k <= 3; ++k) {
    old.push_back(dir + "/shard" + std::to_string(k) + ".gpkg");
    fs::copy_file(s.stores[size_t(k - 1)], old.back());
    test::sql_exec(old.back(), "ALTER TABLE run_input DROP COLUMN role");
  }
  const MergeSummary sum = merge_stores(old, dir + "/merged.gpkg");
  EXPECT_TRUE(sum.complete());
  expect_equal_stores(s.full, dir + "/merged.gpkg");
  const RunRecord want = load_runs(s.full).back(), got = load_runs(dir + "/merged.gpkg").back();
  ASSERT_EQ(got.inputs.size(), want.inputs.size());
  for (size_t i = 0; i < want.inputs.size(); ++i) {
    EXPECT_EQ(got.inputs[i].sha256, want.inputs[i].sha256);
    EXPECT_EQ(got.inputs[i].role, "");  // not known: not made up
  }
  // A batch resumes into an old store: every parcel kept, the new run with its roles.
  const std::string full = dir + "/full.gpkg";
  fs::copy_file(s.full, full);
  test::sql_exec(full, "ALTER TABLE run_input DROP COLUMN role");
  const double done = test::sql_number(full, "SELECT count(*) FROM parcel_job WHERE status IN ('ok','empty')");
  run_town("", {}, nullptr, full, nullptr, true);
  EXPECT_EQ(test::sql_number(full, "SELECT count(*) FROM parcel_job WHERE status IN ('ok','empty') AND run_id = 1"),
            done);
  const auto runs = load_runs(full);
  ASSERT_EQ(runs.size(), 2u);
  EXPECT_EQ(roles_of(runs[0]), std::vector<std::string>(runs[0].inputs.size(), ""));
  EXPECT_EQ(roles_of(runs[1]), (std::vector<std::string>{"cloud", "parcels", "dtm"}));
}

TEST(ShardMerge, SaysWhichShardsAndParcelsAreMissing) {
  const Shards& s = three_shards();
  const std::string dir = test::temp_dir("missing");
  const std::string killed = dir + "/killed.gpkg";  // shard 3 killed after some parcels
  fs::copy_file(s.stores[2], killed);
  test::sql_exec(killed, "PRAGMA foreign_keys = ON; DELETE FROM la_baunit WHERE parcel_id IN (SELECT parcel_id FROM parcel_job ORDER BY layer_index LIMIT 3)");
  test::sql_exec(killed, "UPDATE parcel_job SET status='pending' WHERE parcel_id NOT IN (SELECT parcel_id FROM la_baunit)");
  const MergeSummary sum = merge_stores({s.stores[0], killed}, dir + "/m.gpkg");
  EXPECT_EQ(sum.missing_shards, std::vector<int>{2});
  EXPECT_EQ(sum.pending.size(), 3u);
  EXPECT_EQ(sum.parcels, 13u);
  EXPECT_FALSE(sum.complete());
}

namespace {

std::string read_text(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), {});
}

// summary.json's whole-run fit equals the unsharded run's: counts and ruler
// bins exactly, pooled figures to rounding.
void expect_whole_run_fit(const std::string& summary_path, const nlohmann::json& want) {
  const nlohmann::json j = nlohmann::json::parse(read_text(summary_path));
  ASSERT_EQ(j["any_model_fit"], "computed");
  ASSERT_GT(want["any_model_roof_deviation"]["n"].get<int>(), 1000);
  ASSERT_GT(want["any_model_wall_deviation"]["n"].get<int>(), 100);
  for (const char* key : {"any_model_roof_deviation", "any_model_wall_deviation", "roof_ruler", "wall_ruler"}) {
    EXPECT_EQ(j[key]["n"].get<long>(), want[key]["n"].get<long>()) << key;
    EXPECT_NEAR(j[key]["rmse"].get<double>(), want[key]["rmse"].get<double>(), 1e-12) << key;
  }
  for (const char* key : {"any_model_roof_deviation", "any_model_wall_deviation"}) {
    EXPECT_NEAR(j[key]["mean"].get<double>(), want[key]["mean"].get<double>(), 1e-12) << key;
    EXPECT_NEAR(j[key]["max"].get<double>(), want[key]["max"].get<double>(), 1e-9) << key;
  }
  for (const char* key : {"roof_ruler", "wall_ruler"}) {  // 0.1 mm bins: exact across chunkings
    EXPECT_EQ(j[key]["median"].get<double>(), want[key]["median"].get<double>()) << key;
    EXPECT_EQ(j[key]["p95"].get<double>(), want[key]["p95"].get<double>()) << key;
  }
  EXPECT_EQ(j["wall_points_measured_share"].get<double>(), want["wall_points_measured_share"].get<double>());
}

RunInputs town_inputs(Config cfg = default_config()) { return {sample_town().inputs, std::move(cfg)}; }

}  // namespace

TEST(ShardMerge, MergedWithTheInputsHasTheUnshardedRunsFit) {
  const Shards& s = three_shards();
  const std::string out = test::temp_dir("merged_fit");
  const RunInputs inputs = town_inputs();
  const MergedRun m = merge_run(s.stores, out, {}, false, {}, &inputs);
  EXPECT_EQ(m.fit_missing, "");
  expect_whole_run_fit(out + "/summary.json", s.whole);
}

TEST(ShardMerge, MergedWithoutTheInputsSaysTheFitIsMissing) {
  const Shards& s = three_shards();
  const std::string out = test::temp_dir("merged_nofit");
  const MergedRun m = merge_run(s.stores, out, {}, false);
  EXPECT_NE(m.fit_missing.find("without the batch's inputs"), std::string::npos) << m.fit_missing;
  const nlohmann::json j = nlohmann::json::parse(read_text(out + "/summary.json"));
  EXPECT_EQ(j["any_model_fit"].get<std::string>().rfind("not computed: ", 0), 0u) << j["any_model_fit"];
  for (const char* k : {"any_model_roof_deviation", "any_model_wall_deviation", "roof_ruler", "wall_ruler",
                        "wall_points_measured_share"})
    EXPECT_TRUE(j[k].is_null()) << k << " is " << j[k] << ", not absent";  // no silent zero
  EXPECT_NE(read_text(out + "/report.html").find("whole-run fit of the models not computed"), std::string::npos);
  // A shard missing: no fit either, and why.
  const RunInputs inputs = town_inputs();
  const MergedRun part = merge_run({s.stores[0], s.stores[2]}, test::temp_dir("merged_part"), {}, false, {}, &inputs);
  EXPECT_NE(part.fit_missing.find("missing"), std::string::npos) << part.fit_missing;
}

TEST(ShardMerge, RefusesInputsThatAreNotTheShards) {
  const Shards& s = three_shards();
  auto refused = [&](const RunInputs& inputs, const std::string& says) {
    const std::string out = test::temp_dir("merge_refused");
    try {
      merge_run(s.stores, out, {}, false, {}, &inputs);
      ADD_FAILURE() << "merged, expected a refusal saying " << says;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(out + "/cadastre.gpkg"));  // refused before anything is written
  };
  Config other = default_config();
  other.valuation.tax_rate *= 2;
  refused(town_inputs(other), "other parameters: valuation.tax.rate");
  RunInputs fewer = town_inputs();
  fewer.inputs.parcel_selection.where = "fid < 20";
  refused(fewer, "is not one these inputs select");
  RunInputs no_dtm = town_inputs();
  no_dtm.inputs.dtm.clear();
  refused(no_dtm, "which these inputs lack");
}

TEST(ShardMerge, AStoreEveryShardWroteGivesTheUnshardedRunsFit) {
  const Shards& s = three_shards();
  // The shards into one store (as into one PostgreSQL store): nothing to merge.
  const std::string store = test::temp_dir("shared") + "/cadastre.gpkg";
  for (int k = 1; k <= 3; ++k) run_town("", {k, 3}, nullptr, store);
  const std::string out = test::temp_dir("shared_out");
  const RunInputs inputs = town_inputs();
  const MergedRun m = finish_shared_store(store, out, {}, false, {}, &inputs);
  EXPECT_TRUE(m.merge.complete());
  EXPECT_EQ(m.merge.parcels, 24u);
  expect_whole_run_fit(out + "/summary.json", s.whole);
}
