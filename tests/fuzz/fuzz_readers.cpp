// A seeded mutation fuzzer for every reader (docs/testing.md, "Fuzzing").
// Each target starts from small valid inputs made in code, mutates them and
// feeds each mutant to the reader, which must return or throw InputError:
// any other exception, a crash, a sanitizer report, an input running past
// --input-timeout or an allocation past the sanitizer's cap is a finding.
//
//   fuzz_readers --seconds 120 --seed 1            every target, 2 minutes in all
//   fuzz_readers --target las --seed 7 --seconds 600
//   fuzz_readers --target ply --replay crash.ply   one file, e.g. a finding
#include <cpl_error.h>
#include <cpl_conv.h>
#include <pcl/console/print.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <ctime>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <thread>
#include <unistd.h>

#include "cadastre/parcels.h"
#include "core/config/config.h"
#include "core/error.h"
#include "core/io/dtm_io.h"
#include "core/io/mesh_io.h"
#include "core/io/point_io.h"
#include "core/log.h"
#include "tests/fuzz/fuzz_las_fields.h"
#include "tests/fuzz/fuzz_seeds.h"

#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/common_interface_defs.h>
// Allocations over 1 GiB are findings (a header's claim trusted), as is a
// resident size over 6 GiB; leaks in GDAL/PCL's caches are not this fuzzer's.
extern "C" const char* __asan_default_options() {
  return "max_allocation_size_mb=1024:allocator_may_return_null=0:hard_rss_limit_mb=6144:"
         "detect_leaks=0:abort_on_error=0:print_summary=1";
}
extern "C" const char* __ubsan_default_options() { return "print_stacktrace=1:halt_on_error=1"; }
#endif

namespace fs = std::filesystem;
using namespace c3d;
using namespace c3d::fuzz;

namespace {

using Clock = std::chrono::steady_clock;

// The DTM reader's cell budget here: mutated sizes must not reach the machine's.
constexpr size_t kFuzzDtmCells = size_t(1) << 22;

struct Target {
  std::string name;
  std::function<std::vector<SeedInput>(const std::string& work)> seeds;
  std::function<void(const std::string& path)> read;
  // Where set: the target's own mutations and a read that judges a mutant
  // against its seed (las-fields); otherwise Mutator and `read`.
  std::function<std::string(const SeedInput& seed, uint64_t mixed)> mutate;
  std::function<void(const std::string& path, const SeedInput& seed)> read_against;
};

std::vector<Target> targets() {
  auto cloud = [](const std::string& p) { read_point_cloud(p); };
  return {
      {"las", las_seeds, cloud},
      {"laz", [](const std::string&) { return laz_seeds(); }, cloud},
      {"ply", [](const std::string&) { return ply_seeds(); }, cloud},
      {"pcd", pcd_seeds, cloud},
      {"xyz", [](const std::string&) { return xyz_seeds(); }, cloud},
      {"dtm", [](const std::string&) { return dtm_seeds(); },
       [](const std::string& p) { read_dtm(p, kFuzzDtmCells); }},
      {"parcels", parcel_seeds, [](const std::string& p) { read_parcels(p, parcel_fields("")); }},
      {"config", [](const std::string&) { return config_seeds(); },
       [](const std::string& p) { load_config(p); }},
      {"mesh", [](const std::string&) { return mesh_seeds(); },
       [](const std::string& p) { read_mesh_groups(p); }},
      {"las-fields", las_field_seeds, nullptr,
       [](const SeedInput& s, uint64_t mixed) { return mutate_las_fields(s.bytes, mixed); }, expect_refused_or_same},
  };
}

struct Options {
  double seconds = 120;
  double input_timeout = 10;
  uint64_t seed = 1;
  uint64_t iterations = 0;  // per target; 0: until its share of --seconds is spent
  std::vector<std::string> only;
  std::string work = "fuzz-work";
  std::string replay;
};

// What runs now, for the watchdog and the crash handlers (preformatted:
// a signal handler may only write()).
char g_current[512] = "(starting)";
// When the running input started, on the clock and in process CPU time; 0:
// none runs. CPU time is what counts: CI shares two cores with other tests.
std::atomic<int64_t> g_started_ns{0}, g_started_cpu_ns{0};
double g_input_timeout = 10;
constexpr double kWallFactor = 6;  // an input blocked (not computing) for this many limits hangs too

int64_t now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count();
}

int64_t cpu_ns() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return int64_t(t.tv_sec) * 1000000000 + t.tv_nsec;
}

void report_current() {
  const char head[] = "\nfuzz_readers: the input that failed: ";
  ssize_t ignored = write(2, head, sizeof head - 1);
  ignored = write(2, g_current, strnlen(g_current, sizeof g_current));
  ignored = write(2, "\n", 1);
  (void)ignored;
}

void on_fatal_signal(int sig) {
  report_current();
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

void watchdog() {
  for (;;) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    const int64_t started = g_started_ns.load(), started_cpu = g_started_cpu_ns.load();
    if (!started) continue;
    const double cpu = double(cpu_ns() - started_cpu) * 1e-9, wall = double(now_ns() - started) * 1e-9;
    if (cpu > g_input_timeout || wall > kWallFactor * g_input_timeout) {
      std::fprintf(stderr, "\nfuzz_readers: HANG: one input took %.1f s of CPU (%.1f s on the clock)", cpu, wall);
      report_current();
      std::_Exit(3);
    }
  }
}

// A fresh file each time: truncating one in place makes ext4 flush it on close
// (auto_da_alloc), which cut the fuzzer to a few hundred inputs a second.
void write_file(const std::string& path, const std::string& bytes) {
  std::remove(path.c_str());
  std::ofstream f(path, std::ios::binary);
  f.write(bytes.data(), std::streamsize(bytes.size()));
}

// Runs one input; returns "" when the reader returned or threw InputError.
std::string run_one(const Target& t, const std::string& path, const SeedInput* seed, bool* rejected = nullptr) {
  g_started_cpu_ns = cpu_ns();
  g_started_ns = now_ns();
  std::string finding;
  try {
    if (t.read_against) t.read_against(path, *seed);
    else t.read(path);
  } catch (const InputError&) {
    if (rejected) *rejected = true;
  } catch (const std::exception& e) {
    finding = std::string("exception other than InputError: ") + e.what();
  } catch (...) {
    finding = "a non-std exception";
  }
  g_started_ns = 0;
  return finding;
}

struct Tally {
  uint64_t inputs = 0, rejected = 0, findings = 0;
};

Tally fuzz_target(const Target& t, const Options& o, double seconds) {
  const std::string dir = o.work + "/" + t.name;
  fs::create_directories(dir);
  const std::vector<SeedInput> seeds = t.seeds(dir);
  Tally tally;
  if (seeds.empty()) {
    std::fprintf(stderr, "fuzz_readers: target %s skipped: no seed inputs (../shared absent)\n", t.name.c_str());
    return tally;
  }
  const auto stop = Clock::now() + std::chrono::duration<double>(seconds);
  for (uint64_t i = 0; o.iterations ? i < o.iterations : Clock::now() < stop; ++i) {
    const uint64_t mixed = mix_seed(o.seed, t.name, i);
    const SeedInput& seed = seeds[mixed % seeds.size()];
    Mutator m(mixed);
    const std::string path = dir + "/input" + seed.ext;
    write_file(path, t.mutate ? t.mutate(seed, mixed) : m.mutate(seed));
    std::snprintf(g_current, sizeof g_current,
                  "target %s, seed input %s, --seed %llu, iteration %llu: %s (replay: --target %s "
                  "--replay FILE)",
                  t.name.c_str(), seed.name.c_str(), (unsigned long long)o.seed,
                  (unsigned long long)i, path.c_str(), t.name.c_str());
    ++tally.inputs;
    bool rejected = false;
    const std::string finding = run_one(t, path, &seed, &rejected);
    tally.rejected += rejected;
    if (finding.empty()) continue;
    ++tally.findings;
    const std::string keep = o.work + "/finding-" + t.name + "-" + std::to_string(o.seed) + "-" +
                             std::to_string(i) + seed.ext;
    fs::copy_file(path, keep, fs::copy_options::overwrite_existing);
    std::fprintf(stderr, "FINDING %s: %s (input kept: %s)\n", g_current, finding.c_str(), keep.c_str());
  }
  return tally;
}

// The seed a replayed mutant came from: the one of its size that differs in fewest bytes.
const SeedInput* nearest_seed(const std::vector<SeedInput>& seeds, const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  const std::string bytes{std::istreambuf_iterator<char>(f), {}};
  const SeedInput* best = nullptr;
  size_t fewest = SIZE_MAX;
  for (const SeedInput& s : seeds) {
    if (s.bytes.size() != bytes.size()) continue;
    size_t differ = 0;
    for (size_t i = 0; i < bytes.size(); ++i) differ += bytes[i] != s.bytes[i];
    if (differ < fewest) fewest = differ, best = &s;
  }
  return best;
}

bool parse(int argc, char** argv, Options& o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const char* v = i + 1 < argc ? argv[i + 1] : nullptr;
    if (!v) return false;
    if (a == "--seconds") o.seconds = std::atof(v);
    else if (a == "--input-timeout") o.input_timeout = std::atof(v);
    else if (a == "--seed") o.seed = std::strtoull(v, nullptr, 10);
    else if (a == "--iterations") o.iterations = std::strtoull(v, nullptr, 10);
    else if (a == "--target") o.only.push_back(v);
    else if (a == "--work") o.work = v;
    else if (a == "--replay") o.replay = v;
    else return false;
    ++i;
  }
  return true;
}

void quiet_libraries() {
  CPLSetErrorHandler(CPLQuietErrorHandler);
  CPLSetConfigOption("GDAL_CACHEMAX", "64");
  CPLSetConfigOption("GDAL_DISABLE_READDIR_ON_OPEN", "EMPTY_DIR");
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  log::set_level(log::Level::Off);
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (!parse(argc, argv, o)) {
    std::fprintf(stderr,
                 "usage: fuzz_readers [--seconds S] [--seed N] [--iterations N] [--target NAME]... "
                 "[--work DIR] [--input-timeout S] [--replay FILE]\n");
    return 2;
  }
  quiet_libraries();
  g_input_timeout = o.input_timeout;
  for (int sig : {SIGSEGV, SIGABRT, SIGBUS, SIGFPE, SIGILL}) std::signal(sig, on_fatal_signal);
#if defined(__SANITIZE_ADDRESS__)
  __sanitizer_set_death_callback(report_current);
#endif
  std::thread(watchdog).detach();
  std::vector<Target> chosen;
  for (const Target& t : targets())
    if (o.only.empty() || std::find(o.only.begin(), o.only.end(), t.name) != o.only.end())
      chosen.push_back(t);
  if (chosen.empty()) return std::fprintf(stderr, "fuzz_readers: no such target\n"), 2;
  if (!o.replay.empty()) {
    std::snprintf(g_current, sizeof g_current, "replay of %s", o.replay.c_str());
    const Target& t = chosen.front();
    std::vector<SeedInput> seeds;
    if (t.read_against) seeds = t.seeds(o.work);
    const SeedInput* seed = nearest_seed(seeds, o.replay);
    if (t.read_against && !seed) return std::fprintf(stderr, "fuzz_readers: no seed for %s\n", t.name.c_str()), 2;
    const std::string finding = run_one(t, o.replay, seed);
    std::printf("%s\n", finding.empty() ? "ok (returned or InputError)" : finding.c_str());
    return finding.empty() ? 0 : 1;
  }
  uint64_t findings = 0;
  for (const Target& t : chosen) {
    const auto t0 = Clock::now();
    const Tally tally = fuzz_target(t, o, o.seconds / double(chosen.size()));
    findings += tally.findings;
    std::printf("%-8s %7llu inputs in %5.1f s, %3.0f %% refused with InputError, %llu findings\n",
                t.name.c_str(), (unsigned long long)tally.inputs,
                std::chrono::duration<double>(Clock::now() - t0).count(),
                tally.inputs ? 100.0 * double(tally.rejected) / double(tally.inputs) : 0.0,
                (unsigned long long)tally.findings);
    std::fflush(stdout);
  }
  return findings ? 1 : 0;
}
