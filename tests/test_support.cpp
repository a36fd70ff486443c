#include "tests/test_support.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <sqlite3.h>

#include <array>
#include <cctype>
#include <cmath>
#include <map>
#include <tuple>
#include <sstream>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <functional>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

namespace fs = std::filesystem;

#include "cadastre/store/store.h"
#include "core/config/config.h"
#include "valuation/valuation.h"

namespace c3d::test {

static std::string shared_path(const std::string& sub) {
  fs::path p = fs::path(C3D_SOURCE_DIR).parent_path() / "shared" / sub;
  return fs::exists(p) ? p.string() : std::string();
}

bool in_ci() {
  const char* ci = std::getenv("CI");
  return ci && *ci && std::string(ci) != "false" && std::string(ci) != "0";
}

void note_missing(const std::string& what) {
  if (in_ci()) ADD_FAILURE() << "CI requires it: " << what;
  else std::cout << what << "\n";
}

std::string cimahi_dir() { return shared_path("data/cimahi"); }
std::string schemas_dir() { return shared_path("schemas"); }
std::string laz_dir() { return shared_path("data/laz"); }

// A CityJSONSeq file as one CityJSON file beside it (<file>.city.json): the
// header with every feature's objects, their vertices appended. val3dity 2.6.0
// reads CityJSONSeq from stdin but crashes (SIGSEGV in Surface::~Surface, from
// read_stream_cjseq) freeing a feature that has a MultiSurface, after its
// verdict and before the next feature's; file mode has no such trouble.
static std::string cityjson_of_seq(const std::string& jsonl) {
  std::ifstream in(jsonl);
  nlohmann::json doc;
  for (std::string line; std::getline(in, line);) {
    if (line.empty()) continue;
    nlohmann::json f = nlohmann::json::parse(line);
    if (doc.is_null()) { doc = std::move(f); continue; }  // the header
    const long long offset = static_cast<long long>(doc["vertices"].size());
    std::function<void(nlohmann::json&)> shift = [&](nlohmann::json& j) {
      if (j.is_array()) for (auto& x : j) shift(x);
      else if (j.is_number_integer()) j = j.get<long long>() + offset;
    };
    for (auto& [id, obj] : f["CityObjects"].items()) {
      if (obj.contains("geometry"))
        for (auto& g : obj["geometry"]) shift(g["boundaries"]);
      doc["CityObjects"][id] = obj;
    }
    for (auto& v : f["vertices"]) doc["vertices"].push_back(v);
  }
  const std::string out = jsonl + ".city.json";
  std::ofstream(out) << doc.dump();
  return out;
}

std::optional<std::vector<std::string>> val3dity_invalid(const std::string& cityjson) {
  const std::string tool = shared_path("tools/val3dity/val3dity");
  if (tool.empty()) return std::nullopt;
  const std::string report = cityjson + ".val3dity.json";
  const bool seq = cityjson.size() > 6 && cityjson.compare(cityjson.size() - 6, 6, ".jsonl") == 0;
  if (seq) return val3dity_invalid(cityjson_of_seq(cityjson));
  const std::string cmd = tool + " --report " + report + " " + cityjson + " >/dev/null 2>&1";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  const nlohmann::json r = nlohmann::json::parse(std::ifstream(report));
  std::vector<std::string> invalid;
  for (const auto& f : r.value("features", nlohmann::json::array()))
    if (!f.at("validity").get<bool>()) invalid.push_back(f.at("id").get<std::string>());
  if (invalid.empty() && !r.at("validity").get<bool>()) invalid.push_back("<file>");
  return invalid;
}

const SampleTown& sample_town(const std::string& args) {
  static std::map<std::string, SampleTown> towns;
  auto [at, made] = towns.try_emplace(args);
  if (made) {
    std::string name = "town";  // in the first asking test's folder (ctest runs tests as processes of their own)
    for (char c : args) name += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
    const std::string d = temp_dir(name);
    std::string log;
    EXPECT_EQ(run_cli("sample --out " + d + " " + args, &log), 0) << log;
    at->second = sample_town_files(d);
  }
  return at->second;
}

SampleTown sample_town_files(const std::string& dir) {
  return SampleTown{dir, BatchInputs{{dir + "/cloud.las"}, {}, dir + "/parcels.gpkg", dir + "/dtm.tif"}};
}

std::string temp_dir(const std::string& name) {
  // One directory per build tree and test (ctest -j runs tests of one fixture in
  // parallel processes, and several build trees may run their suites at once).
  std::string test = "global";
  if (const auto* info = ::testing::UnitTest::GetInstance()->current_test_info())
    test = std::string(info->test_suite_name()) + "." + info->name();
  for (char& c : test)
    if (c == '/') c = '_';  // parameterised tests: Suite/Name/0
  fs::path p = fs::path(C3D_TEST_TMP_DIR) / test / name;
  fs::remove_all(p);
  fs::create_directories(p);
  return p.string();
}

std::string shared_run(const std::string& key, const std::function<bool(const std::string& dir)>& fill) {
  const char* root = std::getenv("C3D_SHARED_RUNS");
  if (!root || !*root) {
    const std::string dir = temp_dir(key);
    fill(dir);
    return dir;
  }
  const fs::path dir = fs::path(root) / key, done = dir / ".done";
  fs::create_directories(dir);
  const int lock = ::open((dir.string() + ".lock").c_str(), O_CREAT | O_RDWR, 0644);
  if (lock < 0 || ::flock(lock, LOCK_EX) != 0) ADD_FAILURE() << "cannot lock " << dir << ".lock";
  if (!fs::exists(done)) {
    for (const auto& entry : fs::directory_iterator(dir)) fs::remove_all(entry.path());
    if (fill(dir.string())) std::ofstream(done) << "filled\n";
  }
  if (lock >= 0) ::close(lock);  // releases the lock
  return dir.string();
}

std::string shell(const std::string& cmd, int* rc) {
  std::string out;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) {
    if (rc) *rc = -1;
    return out;
  }
  std::array<char, 4096> buf;
  while (size_t n = fread(buf.data(), 1, buf.size(), pipe)) out.append(buf.data(), n);
  const int status = pclose(pipe);
  if (rc) *rc = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return out;
}

std::string chromium() {
  for (const char* name : {"chromium", "chromium-browser", "google-chrome"}) {
    std::string path = shell("command -v " + std::string(name) + " 2>/dev/null");
    while (!path.empty() && std::isspace(static_cast<unsigned char>(path.back()))) path.pop_back();
    if (!path.empty()) return path;
  }
  return "";
}

int run_cli(const std::string& args, std::string* output) {
  int rc = -1;
  std::string out = shell(std::string(C3D_CLI_PATH) + " " + args + " 2>&1", &rc);
  if (output) *output = out;
  return rc;
}

std::string sample_and_batch(const std::string& dir, const std::string& sample_args, const std::string& batch_args) {
  std::string out;
  if (run_cli("sample " + sample_args + " --out " + dir + "/town", &out) != 0) return "sample: " + out;
  const int rc = run_cli("batch --quiet " + batch_args + " --cloud " + dir + "/town/cloud.las --parcels " + dir +
                             "/town/parcels.gpkg --dtm " + dir + "/town/dtm.tif --out " + dir + "/out",
                         &out);
  return rc == 0 || rc == 3 ? "" : "batch: " + out;
}

std::vector<std::vector<std::string>> parse_csv(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (line.empty()) continue;
    std::vector<std::string> row;
    std::string cell;
    bool quoted = false;
    for (char c : line) {
      if (c == '"') quoted = !quoted;
      else if (c == ',' && !quoted) row.push_back(cell), cell.clear();
      else cell += c;
    }
    row.push_back(cell);
    rows.push_back(row);
  }
  return rows;
}

std::vector<Face> box_shell(const Vec3& lo, const Vec3& hi) {
  auto quad = [](Vec3 a, Vec3 b, Vec3 c, Vec3 d) { return Face{{a, b, c, d}, {}}; };
  const double x0 = lo.x(), y0 = lo.y(), z0 = lo.z(), x1 = hi.x(), y1 = hi.y(), z1 = hi.z();
  return {quad({x0, y0, z0}, {x0, y1, z0}, {x1, y1, z0}, {x1, y0, z0}),
          quad({x0, y0, z1}, {x1, y0, z1}, {x1, y1, z1}, {x0, y1, z1}),
          quad({x0, y0, z0}, {x1, y0, z0}, {x1, y0, z1}, {x0, y0, z1}),
          quad({x1, y1, z0}, {x0, y1, z0}, {x0, y1, z1}, {x1, y1, z1}),
          quad({x0, y1, z0}, {x0, y0, z0}, {x0, y0, z1}, {x0, y1, z1}),
          quad({x1, y0, z0}, {x1, y1, z0}, {x1, y1, z1}, {x1, y0, z1})};
}

void write_solids_cityjson(const std::vector<NamedSolid>& solids, const std::string& path) {
  std::map<std::tuple<long, long, long>, int> index;
  nlohmann::json verts = nlohmann::json::array(), objects = nlohmann::json::object();
  auto ring = [&](const Ring3& r) {
    nlohmann::json ids = nlohmann::json::array();
    for (const auto& p : r) {
      const auto key = std::make_tuple(std::lround(p.x() * 1000), std::lround(p.y() * 1000), std::lround(p.z() * 1000));
      auto [it, added] = index.emplace(key, int(index.size()));
      if (added) verts.push_back({std::get<0>(key), std::get<1>(key), std::get<2>(key)});
      ids.push_back(it->second);
    }
    return ids;
  };
  for (const auto& s : solids) {
    nlohmann::json surfaces = nlohmann::json::array();
    for (const auto& f : s.faces) {
      nlohmann::json one = nlohmann::json::array({ring(f.ring)});
      for (const auto& h : f.holes) one.push_back(ring(h));
      surfaces.push_back(one);
    }
    nlohmann::json g = {{"type", "Solid"}, {"lod", s.lod}, {"boundaries", nlohmann::json::array({surfaces})}};
    objects[s.id] = {{"type", "Building"}, {"geometry", nlohmann::json::array({g})}};
  }
  nlohmann::json doc = {{"type", "CityJSON"}, {"version", "2.0"}, {"CityObjects", objects}, {"vertices", verts}};
  doc["transform"] = {{"scale", {0.001, 0.001, 0.001}}, {"translate", {0, 0, 0}}};
  std::ofstream(path) << doc.dump();
}

std::string write_store(const std::string& path, const BatchModel& m) {
  Store s;
  s.open(path, "", m.epsg);
  s.begin_run("{}", {}, m.frame);
  const Config c = default_config();
  for (size_t i = 0; i < m.parcels.size(); ++i)
    s.write_parcel(m.parcels[i], m.results[i], value_parcel(m.parcels[i], m.results[i], c.valuation), m.frame);
  s.end_run();
  return path;
}

void sql_exec(const std::string& path, const std::string& statement) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  EXPECT_EQ(sqlite3_exec(db, statement.c_str(), nullptr, nullptr, nullptr), SQLITE_OK) << sqlite3_errmsg(db);
  sqlite3_close(db);
}

double sql_number(const std::string& path, const std::string& query) {
  sqlite3* db = nullptr;
  sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr);
  sqlite3_stmt* st = nullptr;
  double v = std::nan("");
  if (sqlite3_prepare_v2(db, query.c_str(), -1, &st, nullptr) == SQLITE_OK && sqlite3_step(st) == SQLITE_ROW)
    v = sqlite3_column_double(st, 0);
  sqlite3_finalize(st);
  sqlite3_close(db);
  return v;
}

}  // namespace c3d::test
