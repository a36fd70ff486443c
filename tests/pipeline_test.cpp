// The batch as a library call (cadastre/batch): a 20-line program gives the
// CLI's models, a sink of one's own receives every parcel once, and --resume
// models a parcel again whenever anything its result depends on changes.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>

#include "cadastre/batch/batch.h"
#include "tests/test_support.h"

using namespace c3d;
namespace fs = std::filesystem;

namespace {

// A small sample town, made once for the whole file.
const test::SampleTown& town() { return test::sample_town("--parcels 4 --seed 3 --density 25"); }

// Holds results in memory; `held` are the keys an earlier run left (what --resume finds).
class MemorySink : public BatchSink {
 public:
  std::vector<std::string> held, keys;
  std::vector<size_t> written;
  void begin(const BatchRun& run) override {
    keys = run.parcel_keys;
    model_.frame = run.frame;
    model_.parcels = *run.parcels;
    model_.results.assign(keys.size(), ParcelResult{});
  }
  bool has_parcel(size_t i, const std::string& key) override { return i < held.size() && held[i] == key; }
  void write_parcel(size_t i, const ParcelResult& r, const ParcelValuation&) override {
    model_.results[i] = r;
    written.push_back(i);
  }
  SinkCounts end() override {
    SinkCounts held;
    for (size_t i : written) ++held.parcels, ++held.by_status[size_t(model_.results[i].status)];
    return held;
  }
  BatchModel models(const std::vector<int>& layer_indices) override {
    BatchModel m;
    m.frame = model_.frame;
    for (int i : layer_indices)
      if (!model_.results[size_t(i)].parcel_id.empty()) {  // written
        m.parcels.push_back(model_.parcels[size_t(i)]);
        m.results.push_back(model_.results[size_t(i)]);
      }
    return m;
  }

 private:
  BatchModel model_;
};

nlohmann::json parcels_of(const std::string& summary_path) {
  std::ifstream f(summary_path);
  return nlohmann::json::parse(f).at("parcels");
}

BatchSettings resume() {
  BatchSettings s;
  s.resume = true;
  return s;
}

}  // namespace

TEST(Pipeline, TwentyLineProgramGivesTheCliModels) {
  const test::SampleTown& t = town();
  const std::string lib = test::temp_dir("lib"), cli = test::temp_dir("cli");
  const std::string cmd = std::string(C3D_MINIMAL_BATCH) + " " + t.inputs.clouds[0] + " " + t.inputs.parcels +
                          " " + t.inputs.dtm + " " + lib + " > " + lib + "/log 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  std::string log;
  ASSERT_EQ(test::run_cli("batch --cloud " + t.inputs.clouds[0] + " --parcels " + t.inputs.parcels + " --dtm " +
                          t.inputs.dtm + " --out " + cli + " --formats cityjson", &log), 0) << log;
  const auto a = parcels_of(lib + "/summary.json"), b = parcels_of(cli + "/summary.json");
  ASSERT_EQ(a.size(), 4u);
  EXPECT_EQ(a, b);
  size_t buildings = 0;
  for (const auto& p : a) buildings += p.at("buildings").size();
  EXPECT_GE(buildings, 3u);
  EXPECT_TRUE(fs::exists(lib + "/buildings.city.json"));
}

TEST(Pipeline, OwnSinkReceivesEveryParcelOnce) {
  MemorySink sink;
  const BatchReport r = run_batch(town().inputs, default_config(), sink);
  std::vector<size_t> written = sink.written;
  std::sort(written.begin(), written.end());
  EXPECT_EQ(written, (std::vector<size_t>{0, 1, 2, 3}));
  EXPECT_EQ(r.reconstructed, 4u);
  EXPECT_EQ(r.failed, 0u);
  EXPECT_EQ(r.held, 4u);
  EXPECT_EQ(r.held_by_status[size_t(ParcelStatus::Ok)] + r.held_by_status[size_t(ParcelStatus::Empty)], 4u);
  EXPECT_GT(r.any_model_roof.n, 1000);  // the models were measured against the points
  EXPECT_LT(r.any_model_roof.rmse, 0.2);
}

TEST(Pipeline, ResumeModelsAParcelAgainWhenAnythingItDependsOnChanges) {
  const Config base = default_config();
  MemorySink first;
  run_batch(town().inputs, base, first);
  MemorySink same;
  same.held = first.keys;
  EXPECT_EQ(run_batch(town().inputs, base, same, resume()).reconstructed, 0u) << "nothing changed";

  const std::vector<std::pair<std::string, std::function<void(Config&)>>> changes = {
      {"outlier_neighbours", [](Config& c) { c.reconstruction.outlier_neighbours = 10; }},
      {"outlier_std", [](Config& c) { c.reconstruction.outlier_std = 3.0; }},
      {"class mapping", [](Config& c) { c.classes.roof.push_back(1); }},
      {"overhang buffer", [](Config& c) { c.clip.overhang_buffer_m = 1.4; }},
      {"valuation", [](Config& c) { c.valuation.tax_rate = 0.002; }},
      {"optimize (effective)", [](Config& c) { c.reconstruction.optimize = true, c.reconstruction.optimize_device = "cpu"; }},
  };
  for (const auto& [what, change] : changes) {
    Config cfg = base;
    change(cfg);
    MemorySink again;
    again.held = first.keys;
    EXPECT_EQ(run_batch(town().inputs, cfg, again, resume()).reconstructed, 4u) << what;
  }
}

TEST(Pipeline, ResumeFollowsTheInputsContentNotTheirNames) {
  MemorySink first;
  run_batch(town().inputs, default_config(), first);
  const std::string dir = test::temp_dir("inputs");
  BatchInputs moved = town().inputs;
  moved.clouds = {dir + "/copy.las"};
  fs::copy_file(town().inputs.clouds[0], moved.clouds[0]);
  MemorySink renamed;
  renamed.held = first.keys;
  EXPECT_EQ(run_batch(moved, default_config(), renamed, resume()).reconstructed, 0u) << "same content";

  // One byte of the last point's intensity changed: the models cannot change, the key must.
  {
    std::fstream f(moved.clouds[0], std::ios::in | std::ios::out | std::ios::binary);
    unsigned short record_length = 0;  // LAS header: point data record length at byte 105
    f.seekg(105);
    f.read(reinterpret_cast<char*>(&record_length), 2);
    f.seekg(0, std::ios::end);
    const std::streamoff size = f.tellg();
    f.seekp(size - record_length + 12);  // X, Y, Z (4 bytes each), then intensity
    f.put(char(0x5a));
  }
  MemorySink edited;
  edited.held = first.keys;
  EXPECT_EQ(run_batch(moved, default_config(), edited, resume()).reconstructed, 4u) << "other content";
}
