// End to end: a real kill -9 in the middle of a batch, --resume to the same
// store as an uninterrupted batch, and an idempotent rerun.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <iostream>
#include <map>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "tests/batch_e2e_support.h"
#include "tests/test_support.h"

using namespace c3d;
using namespace e2e;
using nlohmann::json;

namespace {

// The batch `cmd`, killed (SIGKILL) once some parcels are in `store` and others pending.
void kill_mid_batch(const std::string& dir, const std::string& cmd, const std::string& store) {
  pid_t pid = spawn_cli(cmd, dir + "/killed.log");
  ASSERT_GT(pid, 0);
  JobCounts at_kill;
  bool exited = false;
  int status = 0;
  auto t0 = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() - t0 < std::chrono::seconds(120)) {
    if (waitpid(pid, &status, WNOHANG) == pid) {
      exited = true;
      break;
    }
    at_kill = job_counts(store);
    if (at_kill.done >= 10 && at_kill.pending > 0) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  if (!exited) {
    kill(pid, SIGKILL);
    waitpid(pid, &status, 0);
  }
  ASSERT_FALSE(exited) << "the batch ended before it could be killed:\n"
                       << read_file(dir + "/killed.log");
  ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
}

// Parcels are whole: every stored parcel has its job row done, its spatial
// unit, valuation, buildings and elements, equal to the uninterrupted run;
// pending parcels have nothing stored.
void expect_whole_parcels(const std::string& store, Snapshot& want, int parcels) {
  Sqlite db(store);
  ASSERT_TRUE(db.ok()) << db.error();
  EXPECT_EQ(db.text("PRAGMA integrity_check"), "ok");
  EXPECT_TRUE(db.rows("PRAGMA foreign_key_check").empty());
  JobCounts after = job_counts(store);
  ASSERT_GT(after.done, 0);
  ASSERT_GT(after.pending, 0) << "killed too late to test anything";
  EXPECT_EQ(after.done + after.pending, parcels);
  std::cout << "killed with " << after.done << " parcels stored, " << after.pending
            << " pending\n";
  Snapshot got = snapshot(store);
  std::map<std::string, std::string> job_status;
  for (const auto& r : got["parcel_job"]) job_status[r[0].s] = r[2].s;
  std::set<std::string> stored;
  for (const auto& r : got["la_spatialunit"]) stored.insert(r[0].s);
  EXPECT_EQ(long(stored.size()), after.done);
  for (const auto& [pid_s, st] : job_status)
    EXPECT_EQ(stored.count(pid_s) > 0, st != "pending") << pid_s << " is " << st;
  std::map<std::string, std::set<std::string>> buildings_of;
  for (const auto& r : want["building"]) buildings_of[r[0].s].insert(r[1].s);
  for (const auto& r : got["building"]) buildings_of[r[0].s].insert(r[1].s);
  for (const std::string& p : stored) {
    const auto& bids = buildings_of[p];
    if (job_status[p] == "ok") EXPECT_FALSE(bids.empty()) << p;
    for (const char* t : {"la_spatialunit", "building", "building_element", "vm_valuation"}) {
      bool by_b = std::string(t) == "building_element";
      EXPECT_EQ(diff_rows(rows_of_parcel(got[t], p, bids, by_b),
                          rows_of_parcel(want[t], p, bids, by_b)),
                "")
          << "parcel " << p << " in " << t;
    }
  }
  for (const auto& r : got["building"]) {
    const std::string& bid = r[1].s;
    size_t n = 0;
    for (const auto& e : got["building_element"]) n += e[0].s == bid;
    EXPECT_GT(n, 0u) << "building " << bid << " stored without elements";
  }
}

// Rerun into the same output without --resume: everything redone, nothing doubled.
void expect_rerun_idempotent(const std::string& cmd, const std::string& ref, const Snapshot& want) {
  std::string log;
  auto counts = [](const std::string& path) {
    Sqlite db(path);
    std::map<std::string, double> c;
    for (const char* t : {"la_party", "la_baunit", "la_rrr", "la_spatialunit", "building",
                          "building_element", "vm_valuationunit", "vm_valuation", "vm_cost_item",
                          "parcel_job"})
      c[t] = db.number(std::string("SELECT count(*) FROM ") + t);
    c["runs"] = db.number("SELECT count(*) FROM run");
    return c;
  };
  auto before = counts(ref + "/cadastre.gpkg");
  int rc = test::run_cli(cmd, &log);
  ASSERT_TRUE(rc == 0 || rc == 3) << "exit code " << rc << "\n" << log;
  auto after = counts(ref + "/cadastre.gpkg");
  for (const auto& [t, n] : before) {
    if (t == "runs") EXPECT_EQ(after[t], n + 1) << "one run record per batch";
    else EXPECT_EQ(after[t], n) << t << " rows after the rerun";
  }
  expect_same_store(want, snapshot(ref + "/cadastre.gpkg"), "rerun vs first run");
  Sqlite db(ref + "/cadastre.gpkg");
  EXPECT_TRUE(db.rows("SELECT parcel_id FROM la_spatialunit GROUP BY parcel_id HAVING count(*) > 1")
                  .empty());
  EXPECT_TRUE(db.rows("SELECT building_fid, element_index FROM building_element "
                      "GROUP BY building_fid, element_index HAVING count(*) > 1")
                  .empty());
  EXPECT_TRUE(db.rows("SELECT valuationunit_id FROM vm_valuation GROUP BY valuationunit_id "
                      "HAVING count(*) > 1")
                  .empty());
}

}  // namespace

TEST(BatchE2E, KilledBatchResumesToTheSameStoreAndRerunIsIdempotent) {
  std::string dir = test::temp_dir("batch_e2e_kill");
  std::string town = dir + "/town", ref = dir + "/ref", run = dir + "/run";
  const int kParcels = 200;
  // Fewer points than the default keep the three batches within a minute or so.
  make_town(town, kParcels, 11, "--density 10 --wall-density 5");
  const std::string args = " --jobs 1 --quiet --formats cityjson";

  // The uninterrupted reference.
  std::string log;
  int rc = test::run_cli(batch_args(town, ref) + args, &log);
  ASSERT_TRUE(rc == 0 || rc == 3) << "exit code " << rc << "\n" << log;
  Snapshot want = snapshot(ref + "/cadastre.gpkg");
  ASSERT_EQ(want["la_spatialunit"].size(), size_t(kParcels));
  ASSERT_EQ(want["vm_valuation"].size(), size_t(kParcels));
  ASSERT_GT(want["building"].size(), size_t(kParcels) / 2);
  ASSERT_GT(want["building_element"].size(), want["building"].size());

  fs::create_directories(run);
  const std::string store = run + "/cadastre.gpkg";
  ASSERT_NO_FATAL_FAILURE(kill_mid_batch(dir, batch_args(town, run) + args, store));
  ASSERT_NO_FATAL_FAILURE(expect_whole_parcels(store, want, kParcels));

  // Resume to completion: the store equals the uninterrupted one.
  rc = test::run_cli(batch_args(town, run) + args + " --resume", &log);
  ASSERT_TRUE(rc == 0 || rc == 3) << "exit code " << rc << "\n" << log;
  {
    Sqlite db(store);
    EXPECT_EQ(db.text("PRAGMA integrity_check"), "ok");
    EXPECT_EQ(db.number("SELECT count(*) FROM parcel_job WHERE status = 'pending'"), 0.0);
  }
  expect_same_store(want, snapshot(store), "resumed vs uninterrupted");
  json summary = json::parse(read_file(run + "/summary.json"));
  EXPECT_EQ(summary["parcels"].size(), size_t(kParcels));

  ASSERT_NO_FATAL_FAILURE(expect_rerun_idempotent(batch_args(town, ref) + args, ref, want));
}
