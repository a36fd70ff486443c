// The batch's output folder, end to end (issue 35): one batch per OUT at a
// time, another run's store refused unless --resume or --overwrite, outputs
// that appear whole or not at all with run.finished set last, a full disk as a
// clean error that --resume completes, --jobs and --formats checked before any
// work, and progress for every stage.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sys/file.h>
#include <sys/resource.h>

#include <chrono>
#include <csignal>
#include <thread>

#include "tests/batch_e2e_support.h"
#include "tests/test_support.h"

using namespace c3d;
using namespace e2e;
using nlohmann::json;

namespace {

std::string run(const std::string& args, int* rc) {
  std::string out;
  *rc = test::run_cli(args, &out);
  return out;
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

std::string run_finished(const std::string& store) {
  Sqlite db(store);
  auto rows = db.rows("SELECT finished FROM run ORDER BY fid DESC LIMIT 1");
  return rows.empty() || rows[0][0].null ? std::string() : rows[0][0].s;
}

size_t parcels_in_summary(const std::string& out) {
  return json::parse(read_file(out + "/summary.json"))["parcels"].size();
}

// The batch `args` as a child with its file size limited to `bytes`; its exit code.
int run_with_file_limit(const std::string& args, rlim_t bytes, const std::string& log) {
  int status = 0;
  waitpid(spawn_cli(args, log, bytes), &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

}  // namespace

TEST(OutDir, ASecondBatchOnTheSameFolderIsRefusedWhileTheFirstHoldsIt) {
  const std::string dir = test::temp_dir("lock");
  make_town(dir + "/town", 4, 2);
  const std::string out = dir + "/out";
  fs::create_directories(out);
  // The first batch's lock, held here (flock: the same advisory lock a batch takes).
  int fd = open((out + "/.cadastre3d.lock").c_str(), O_RDWR | O_CREAT, 0644);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(flock(fd, LOCK_EX | LOCK_NB), 0);
  int rc = 0;
  std::string log = run(batch_args(dir + "/town", out), &rc);
  EXPECT_EQ(rc, 1) << log;
  EXPECT_TRUE(has(log, out + ": another cadastre3d command")) << log;
  EXPECT_FALSE(fs::exists(out + "/cadastre.gpkg")) << "refused before writing anything";
  close(fd);  // released: the next batch runs
  log = run(batch_args(dir + "/town", out) + " --quiet", &rc);
  EXPECT_EQ(rc, 0) << log;
}

TEST(OutDir, TwoBatchesStartedTogetherOneIsRefused) {
  const std::string dir = test::temp_dir("together");
  make_town(dir + "/town", 8, 4);
  const std::string out = dir + "/out";
  pid_t first = spawn_cli(batch_args(dir + "/town", out) + " --quiet", dir + "/first.log");
  // Wait until the first batch has its store open (it holds the lock by then).
  for (int i = 0; i < 3000 && job_counts(out + "/cadastre.gpkg").done < 0; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  int rc = 0;
  std::string log = run(batch_args(dir + "/town", out), &rc);
  int status = 0;
  waitpid(first, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << read_file(dir + "/first.log");
  EXPECT_EQ(rc, 1) << log;
  EXPECT_TRUE(has(log, "another cadastre3d command")) << log;
  Sqlite db(out + "/cadastre.gpkg");
  EXPECT_EQ(db.number("SELECT count(*) FROM run"), 1) << "only the first batch ran";
  EXPECT_EQ(db.number("SELECT parcels_ok + parcels_empty + parcels_failed FROM run"), 8);
}

TEST(OutDir, AnotherDataSetIntoAFolderWithAStoreIsRefusedUnlessResumeOrOverwrite) {
  const std::string dir = test::temp_dir("other_run");
  make_town(dir + "/a", 6, 2);
  make_town(dir + "/b", 4, 7);
  const std::string out = dir + "/out";
  int rc = 0;
  std::string log = run(batch_args(dir + "/a", out) + " --quiet", &rc);
  ASSERT_EQ(rc, 0) << log;
  log = run(batch_args(dir + "/b", out) + " --quiet", &rc);
  EXPECT_EQ(rc, 1) << log;
  EXPECT_TRUE(has(log, out + "/cadastre.gpkg: holds 6 parcel(s) of another run")) << log;
  EXPECT_EQ(parcels_in_summary(out), 6u) << "the first run's outputs are untouched";
  // The same run again is no other run: a rerun is allowed.
  log = run(batch_args(dir + "/a", out) + " --quiet", &rc);
  EXPECT_EQ(rc, 0) << log;
  log = run(batch_args(dir + "/b", out) + " --overwrite --quiet", &rc);
  EXPECT_EQ(rc, 0) << log;
  EXPECT_EQ(parcels_in_summary(out), 4u) << "--overwrite replaces the store";
  Sqlite db(out + "/cadastre.gpkg");
  EXPECT_EQ(db.number("SELECT count(*) FROM la_spatialunit"), 4);
  log = run(batch_args(dir + "/a", out) + " --resume --quiet", &rc);
  EXPECT_EQ(rc, 0) << log;
  // Both towns number their parcels alike: this run's replace the stored ones of the same id.
  EXPECT_EQ(parcels_in_summary(out), 6u) << "--resume keeps the store and adds this run's parcels";
  log = run(batch_args(dir + "/b", out) + " --resume", &rc);
  EXPECT_EQ(rc, 0) << log;
  EXPECT_TRUE(has(log, "batch: 4 parcels; the store holds 6 in ")) << log;
  log = run(batch_args(dir + "/a", out) + " --resume --overwrite", &rc);
  EXPECT_EQ(rc, 2) << log;
}

TEST(OutDir, AnOutputThatCannotBeWrittenLeavesTheRunUnfinished) {
  const std::string dir = test::temp_dir("unfinished");
  make_town(dir + "/town", 4, 3);
  const std::string out = dir + "/out";
  fs::create_directories(out + "/buildings.city.json/in_the_way");  // a folder where the export goes
  int rc = 0;
  std::string log = run(batch_args(dir + "/town", out) + " --formats cityjson --quiet", &rc);
  EXPECT_EQ(rc, 1) << log;
  EXPECT_TRUE(has(log, "buildings.city.json")) << log;
  EXPECT_EQ(run_finished(out + "/cadastre.gpkg"), "") << "finished is set only once every output is in place";
  fs::remove_all(out + "/buildings.city.json");
  log = run(batch_args(dir + "/town", out) + " --formats cityjson --quiet", &rc);
  EXPECT_EQ(rc, 0) << log;
  EXPECT_NE(run_finished(out + "/cadastre.gpkg"), "");
}

TEST(OutDir, ABatchKilledWhileWritingOutputsLeavesNoPartFileAndAnUnfinishedRun) {
  const std::string dir = test::temp_dir("killed_outputs");
  make_town(dir + "/town", 30, 6);
  const std::string out = dir + "/out", store = out + "/cadastre.gpkg";
  pid_t pid = spawn_cli(batch_args(dir + "/town", out) + " --formats gml,cityjson,ifc,obj --jobs 2",
                        dir + "/killed.log");
  // The outputs begin once every parcel is stored: kill at the first sign of them.
  bool writing = false;
  auto t0 = std::chrono::steady_clock::now();
  while (!writing && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(120)) {
    writing = fs::exists(out + "/.staging") || fs::exists(out + "/summary.json");
    if (!writing) std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  kill(pid, SIGKILL);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(writing) << read_file(dir + "/killed.log");
  ASSERT_TRUE(WIFSIGNALED(status)) << "the batch ended before it could be killed";
  EXPECT_EQ(run_finished(store), "") << "killed before its outputs were in place";
  // Whatever is in OUT itself is whole: JSON parses, the report ends.
  if (fs::exists(out + "/summary.json")) EXPECT_NO_THROW(json::parse(read_file(out + "/summary.json")));
  if (fs::exists(out + "/buildings.city.json"))
    EXPECT_NO_THROW(json::parse(read_file(out + "/buildings.city.json")));
  if (fs::exists(out + "/report.html")) EXPECT_TRUE(has(read_file(out + "/report.html"), "</html>"));
  // The next batch clears the leftovers and finishes.
  int rc = 0;
  std::string log = run(batch_args(dir + "/town", out) + " --resume --quiet", &rc);
  EXPECT_EQ(rc, 0) << log;
  EXPECT_FALSE(fs::exists(out + "/.staging"));
  EXPECT_NE(run_finished(store), "");
}

TEST(OutDir, AFullDiskIsACleanErrorTheStoreStaysWholeAndResumeCompletesIt) {
  const std::string dir = test::temp_dir("disk_full");
  make_town(dir + "/town", 40, 3);
  const std::string out = dir + "/out", store = out + "/cadastre.gpkg";
  // Enough for the store's tables and a few parcels, not for all 40.
  const int rc = run_with_file_limit(batch_args(dir + "/town", out) + " --quiet", 1000000, dir + "/full.log");
  const std::string log = read_file(dir + "/full.log");
  EXPECT_EQ(rc, 1) << log;
  EXPECT_TRUE(has(log, "cadastre3d: error: " + store + ": ")) << log;
  EXPECT_TRUE(has(log, "(is the disk full?)")) << log;
  EXPECT_FALSE(has(log, "terminate")) << log;
  {
    Sqlite db(store);
    EXPECT_EQ(db.text("PRAGMA integrity_check"), "ok");
    EXPECT_TRUE(db.rows("PRAGMA foreign_key_check").empty());
    const JobCounts jobs = job_counts(store);
    EXPECT_GT(jobs.pending, 0) << log;
    // Each stored parcel whole, the failed one rolled back: a spatial unit and
    // a valuation for every parcel done, none for a pending one.
    EXPECT_EQ(db.number("SELECT count(*) FROM la_spatialunit"), jobs.done);
    EXPECT_EQ(db.number("SELECT count(*) FROM vm_valuation"), jobs.done);
    EXPECT_EQ(run_finished(store), "");
  }
  std::string again;
  EXPECT_EQ(test::run_cli(batch_args(dir + "/town", out) + " --resume --quiet", &again), 0) << again;
  const JobCounts jobs = job_counts(store);
  EXPECT_EQ(jobs.done, 40);
  EXPECT_EQ(jobs.pending, 0);
  EXPECT_NE(run_finished(store), "");
}

TEST(OutDir, JobsAndFormatsAreCheckedBeforeAnyWork) {
  const std::string dir = test::temp_dir("options");
  make_town(dir + "/town", 3, 5);
  const std::string out = dir + "/out";
  int rc = 0;
  for (const char* jobs : {"0", "-2", "x"}) {
    std::string log = run(batch_args(dir + "/town", out) + " --jobs " + jobs, &rc);
    EXPECT_EQ(rc, 2) << jobs << ": " << log;
    EXPECT_TRUE(has(log, "--jobs")) << log;
  }
  const auto t0 = std::chrono::steady_clock::now();
  std::string log = run(batch_args(dir + "/town", out) + " --formats cityjson,cityjsn", &rc);
  EXPECT_EQ(rc, 2) << log;
  EXPECT_TRUE(has(log, "cityjsn")) << log;
  EXPECT_FALSE(fs::exists(out + "/cadastre.gpkg")) << "caught before any work";
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
  // Far more threads than cores: clamped, with a warning, and the batch runs.
  log = run(batch_args(dir + "/town", out) + " --jobs 100000 --quiet", &rc);
  EXPECT_EQ(rc, 0) << log;
  EXPECT_TRUE(has(log, "warning: --jobs 100000 is more than 4 per core; using ")) << log;
}

TEST(OutDir, EveryStageReportsProgressAndTheLastLineCountsStatuses) {
  const std::string dir = test::temp_dir("progress");
  make_town(dir + "/town", 6, 8);
  int rc = 0;
  // stderr is a pipe here: log lines, not a bar.
  const std::string log = run(batch_args(dir + "/town", dir + "/out"), &rc);
  ASSERT_EQ(rc, 0) << log;
  for (const char* line : {"cadastre3d: ingest 3/3 done in ", "cadastre3d: reconstruct 6/6 done in ",
                           "cadastre3d: store 1/1 done in ", "cadastre3d: outputs "})
    EXPECT_TRUE(has(log, line)) << line << "\n" << log;
  const json summary = json::parse(read_file(dir + "/out/summary.json"));
  const std::string counts = "parcels: " + std::to_string(summary["parcels_ok"].get<int>()) + " ok, " +
                             std::to_string(summary["parcels_empty"].get<int>()) + " empty, " +
                             std::to_string(summary["parcels_failed"].get<int>()) + " failed, 0 suspect";
  EXPECT_TRUE(has(log, counts)) << counts << "\n" << log;
  EXPECT_FALSE(has(log, "\r")) << "no bar in a log";
}

TEST(OutDir, AStoreFileWithoutTablesLeftByAKilledBatchIsTakenOverButAForeignFileIsNot) {
  const std::string dir = test::temp_dir("empty_store");
  make_town(dir + "/town", 4, 2);
  const std::string out = dir + "/out", store = out + "/cadastre.gpkg";
  int rc = 0;
  // What a batch killed before its schema committed leaves: an empty file, or
  // one with the GeoPackage header only.
  for (const bool header : {false, true}) {
    fs::remove_all(out);
    fs::create_directories(out);
    std::ofstream(store).close();
    if (header) test::sql_exec(store, "PRAGMA application_id = 1196444487; PRAGMA user_version = 10300;");
    const std::string log = run(batch_args(dir + "/town", out) + " --quiet", &rc);
    EXPECT_EQ(rc, 0) << log;
    EXPECT_GT(Sqlite(store).number("SELECT count(*) FROM la_spatialunit"), 0) << log;
  }
  fs::remove_all(out);
  fs::create_directories(out);
  std::ofstream(store) << "not a database\n";
  const std::string log = run(batch_args(dir + "/town", out) + " --quiet", &rc);
  EXPECT_EQ(rc, 1) << log;
  EXPECT_TRUE(has(log, store + ": not a GeoPackage or SQLite file")) << log;
  EXPECT_EQ(read_file(store), "not a database\n") << "a foreign file is left as it was";
}

// `report` and `export` into a batch's folder take its lock (refused in one
// line while a batch holds it, OUT untouched), write whole files or none (a
// report that cannot finish leaves the batch's report.csv as it was, not
// empty) and replace their folders whole (no page of an earlier report stays).
TEST(OutDir, ReportAndExportTakeTheLockAndWriteWholeFiles) {
  const std::string dir = test::temp_dir("report_export");
  make_town(dir + "/town", 4, 2);
  const std::string out = dir + "/out", store = out + "/cadastre.gpkg";
  int rc = 0;
  std::string log = run(batch_args(dir + "/town", out) + " --quiet", &rc);
  ASSERT_EQ(rc, 0) << log;
  const std::string csv = read_file(out + "/report.csv"), ifc = read_file(out + "/buildings.ifc");
  {
    int fd = open((out + "/.cadastre3d.lock").c_str(), O_RDWR | O_CREAT, 0644);
    ASSERT_EQ(flock(fd, LOCK_EX | LOCK_NB), 0);
    for (const std::string cmd : {"report", "export"}) {
      log = run(cmd + " --store " + store + " --out " + out, &rc);
      EXPECT_EQ(rc, 1) << log;
      EXPECT_TRUE(has(log, out + ": another cadastre3d command")) << log;
    }
    close(fd);
  }
  EXPECT_EQ(read_file(out + "/report.csv"), csv);
  int status = 0;
  waitpid(spawn_cli("report --store " + store + " --out " + out, dir + "/limited.log", 1000), &status, 0);
  EXPECT_FALSE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << read_file(dir + "/limited.log");
  EXPECT_EQ(read_file(out + "/report.csv"), csv) << "a report that could not finish changed OUT";
  waitpid(spawn_cli("export --formats ifc --store " + store + " --out " + out, dir + "/limited.log", 1000), &status, 0);
  EXPECT_EQ(read_file(out + "/buildings.ifc"), ifc) << "an export that could not finish changed OUT";

  std::ofstream(out + "/report/parcels-999.html") << "an earlier report's page";
  fs::create_directories(out + "/obj");
  std::ofstream(out + "/obj/gone.obj") << "an earlier export's building";
  for (const std::string cmd : {"report", "export --formats obj"}) {
    log = run(cmd + " --store " + store + " --out " + out, &rc);
    EXPECT_EQ(rc, 0) << log;
  }
  EXPECT_FALSE(fs::exists(out + "/report/parcels-999.html"));
  EXPECT_FALSE(fs::exists(out + "/obj/gone.obj"));
  EXPECT_FALSE(fs::exists(out + "/.staging"));
  EXPECT_EQ(read_file(out + "/report.csv"), csv);
  EXPECT_TRUE(fs::exists(out + "/report.html"));
}
