#pragma once
// Helpers shared by the tests: where the shared data is, temp dirs, running the
// CLI, a box-shaped shell.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "cadastre/batch/batch.h"
#include "core/types.h"

namespace c3d::test {

// Whether this is a CI run (CI set and not "false" or "0"): there every
// requirement of a test must be present (C3D_NEED).
bool in_ci();
// A judge missing where the test goes on with a weaker check: a failure in
// CI, a printed note elsewhere.
void note_missing(const std::string& what);

// ../shared/data/cimahi beside the checkout, or "" when absent (tests then skip).
std::string cimahi_dir();
std::string schemas_dir();
// ../shared/data/laz (LAS/LAZ pairs with known hashes), or "" when absent.
std::string laz_dir();
// A fresh empty directory under the build's temp area (<build>/tests/tmp/<Suite.Test>/name),
// so tests running in parallel never share one.
std::string temp_dir(const std::string& name);
// A folder that `fill` makes once per ctest run for every test process asking
// for `key` (ctest runs each test as a process of its own): ctest sets
// C3D_SHARED_RUNS and empties it first (the fixture Tests.SharedRunsEmptied);
// the first process to lock the key fills the folder, the others wait and
// reuse it. Without C3D_SHARED_RUNS (a test binary run by hand) each process
// fills a temp_dir of its own. A failed fill (false) is not kept: the next
// process tries again and fails with its own message.
std::string shared_run(const std::string& key, const std::function<bool(const std::string& dir)>& fill);

// A sample town, `cadastre3d sample --out DIR ARGS`, made once per test binary
// and argument list (a failure fails the test that first asks), and its files
// as a batch takes them.
struct SampleTown {
  std::string dir;
  BatchInputs inputs;
};
const SampleTown& sample_town(const std::string& args);
// The files of the sample town `cadastre3d sample` wrote into `dir`.
SampleTown sample_town_files(const std::string& dir);

// Closed shells as CityJSON, one Building object per solid (vertices on a
// 1 mm grid), for val3dity to judge shells that no export writes alone.
struct NamedSolid {
  std::string id, lod;
  std::vector<Face> faces;
};
void write_solids_cityjson(const std::vector<NamedSolid>& solids, const std::string& path);

// `m` written to a fresh store at `path` (valued with the default
// configuration), as a batch would; returns path.
std::string write_store(const std::string& path, const BatchModel& m);
// Runs an SQL statement on the SQLite file at `path` (the test fails if it does).
void sql_exec(const std::string& path, const std::string& statement);
// The first column of the first row `query` gives on the SQLite file at
// `path`, read-only; NaN when there is none.
double sql_number(const std::string& path, const std::string& query);
// The reference validator's verdict on a CityJSON file: the ids of the
// features ../shared/tools/val3dity finds invalid ("<file>" when the file
// itself fails with no feature named); nullopt when val3dity is absent. A
// ".jsonl" file (CityJSONSeq) is judged as one CityJSON file of its features.
std::optional<std::vector<std::string>> val3dity_invalid(const std::string& cityjson);
// What `sh -c cmd` prints on stdout (redirect stderr in cmd to keep or drop
// it), its exit status in *rc (-1 when it did not exit).
std::string shell(const std::string& cmd, int* rc = nullptr);
// The path of the first of chromium, chromium-browser, google-chrome on PATH; "" when none.
std::string chromium();
// Runs the cadastre3d binary with the given argument string; returns the exit
// code and fills output with stdout+stderr.
int run_cli(const std::string& args, std::string* output = nullptr);
// `sample <sample_args> --out DIR/town`, then `batch --quiet <batch_args>` on
// its cloud, parcels and DTM into DIR/out: "" when both ran (the batch may
// exit 3, some parcels not ok), else which failed and its output.
std::string sample_and_batch(const std::string& dir, const std::string& sample_args,
                             const std::string& batch_args = "");

// Closed shell of the axis-aligned box [lo, hi], faces outward.
std::vector<Face> box_shell(const Vec3& lo, const Vec3& hi);

// Rows of a CSV text (quoted fields may hold commas; blank lines skipped).
std::vector<std::vector<std::string>> parse_csv(const std::string& text);

}  // namespace c3d::test

// A test's requirement (a service, a judge, ../shared): without it the test
// skips with `what`, but in CI (CI=true, .ci/run) it fails naming it, so a
// missing install step cannot pass as green.
#define C3D_NEED(have, what)                                                         \
  do {                                                                               \
    if (!(have)) {                                                                   \
      if (c3d::test::in_ci()) FAIL() << "CI requires it: " << what;                  \
      GTEST_SKIP() << what;                                                          \
    }                                                                                \
  } while (0)

#define C3D_REQUIRE_CIMAHI() C3D_NEED(!c3d::test::cimahi_dir().empty(), "../shared/data/cimahi not found beside the checkout")
