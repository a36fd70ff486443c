// Shards of a batch (--shard K/N) and their merge (issue 37): the shards
// cover the layer once, a shard stores only its own parcels, and the merged
// shards equal one unsharded run: parcels, statuses, element areas, NJOP, tax.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <set>

#include "cadastre/batch/merge.h"
#include "cadastre/batch/shard.h"
#include "cadastre/batch/store_sink.h"
#include "cadastre/store.h"
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

const test::SampleTown& sample_town() { return test::sample_town("--parcels 24 --seed 3"); }

// Runs the sample town (one shard of it, or all) into a fresh store.
std::string run_town(const std::string& name, Shard shard = {}) {
  const std::string store = test::temp_dir(name) + "/cadastre.gpkg";
  StoreSink sink(store);
  BatchSettings settings;
  settings.jobs = 2;
  settings.shard = shard;
  run_batch(sample_town().inputs, default_config(), sink, settings);
  return store;
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

struct Shards {
  std::string full;
  std::vector<std::string> stores;  // shard 1..3 of 3
};

const Shards& three_shards() {
  static const Shards s = [] {
    Shards r{run_town("full"), {}};
    for (int k = 1; k <= 3; ++k) r.stores.push_back(run_town("shard" + std::to_string(k), {k, 3}));
    return r;
  }();
  return s;
}

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
  for (size_t i = 0; i < want.inputs.size(); ++i) EXPECT_EQ(got.inputs[i].sha256, want.inputs[i].sha256);
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
