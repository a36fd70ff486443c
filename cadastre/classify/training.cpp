#include "cadastre/classify/training.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>

#include "cadastre/parcels.h"
#include "core/classify/classify.h"
#include "core/geometry/geometry.h"
#include "core/io/dtm_io.h"
#include "core/io/point_io.h"
#include "core/log.h"

namespace c3d {
namespace {

constexpr int kHeldOutParcelEvery = 3;  // Cimahi: parcels 2, 5, 8, ... in layer order are held out
constexpr int kTownParcels = 20;        // two blocks of 2 x 5: every layout, streets, open land

// A survey kind: densities per m2 (roof, wall, open ground), noise, trees and
// garden sheds per parcel (low roofs beside trees: without them a forest
// learns that low and small is vegetation, and misses every annex).
struct Survey {
  double roof, wall, ground, noise, trees, sheds;
};
constexpr Survey kSurveys[] = {
    {10, 1.5, 6, 0.05, 2.0, 0.6},  // airborne: a few facade returns, dense ground
    {40, 20, 3, 0.03, 1.5, 0.4},   // UAV roofs with handheld walls (Cimahi's kind)
    {80, 4, 8, 0.04, 1.0, 0.4},    // dense UAV, oblique facade returns
};

SampleOptions town(std::uint64_t seed) {
  const Survey& s = kSurveys[seed % 3];
  SampleOptions o;
  o.seed = seed;
  o.parcels = kTownParcels;
  o.roof_density = s.roof;
  o.wall_density = s.wall;
  o.ground_density = s.ground;
  o.roof_noise = s.noise;
  o.wall_noise = s.noise;
  o.trees_per_parcel = s.trees;
  o.sheds_per_parcel = s.sheds;
  return o;
}

PointClass sample_label(std::uint8_t cls, PointTag tag) {
  if (cls == 2) return PointClass::Ground;
  if (cls == 64) return PointClass::Wall;
  if (cls == 6 && tag == PointTag::Surface) return PointClass::Roof;
  return PointClass::Other;
}

bool in_parcel(const Parcel& parcel, const Vec2& p) {
  for (const auto& poly : parcel.shape)
    if (in_polygon_plan(poly, p)) return true;
  return false;
}

LabelledSet subset(const LabelledSet& all, const std::vector<size_t>& rows, const std::string& name) {
  LabelledSet s;
  s.name = name;
  s.features.rows = rows.size();
  s.features.values.reserve(rows.size() * kFeatureCount);
  for (size_t r : rows) {
    s.features.values.insert(s.features.values.end(), all.features.row(r), all.features.row(r) + kFeatureCount);
    s.labels.push_back(all.labels[r]);
  }
  return s;
}

// Cimahi: roof (class 6) and wall (64) points; its parcels split into trained and held out.
void add_cimahi(const std::string& dir, TrainingData& data) {
  namespace fs = std::filesystem;
  const PointCloud cloud = read_point_cloud((fs::path(dir) / "cimahi.las").string());
  const Dtm dtm = read_dtm((fs::path(dir) / "dtm.tif").string());
  const ParcelLayer layer = read_parcels((fs::path(dir) / "parcels.shp").string());
  LabelledSet all;
  all.features = cloud_features(cloud.points, dtm);
  for (auto c : cloud.classes) all.labels.push_back(c == 64 ? PointClass::Wall : PointClass::Roof);
  std::vector<size_t> train, held;
  for (size_t i = 0; i < cloud.points.size(); ++i) {
    const Vec2 p = cloud.points[i].head<2>();
    for (const auto& parcel : layer.parcels) {
      if (!in_parcel(parcel, p)) continue;
      (parcel.index % kHeldOutParcelEvery == kHeldOutParcelEvery - 1 ? held : train).push_back(i);
      break;
    }
  }
  data.train.push_back(subset(all, train, "Cimahi, trained parcels"));
  data.held_out.push_back(subset(all, held, "Cimahi, held-out parcels"));
}

// Fisher-Yates on raw mt19937_64 output: the same draw on every standard library.
std::vector<size_t> draw(std::vector<size_t> rows, long n, std::mt19937_64& rng) {
  for (size_t i = rows.size(); i > 1; --i) std::swap(rows[i - 1], rows[rng() % i]);
  if (long(rows.size()) > n) rows.resize(size_t(n));
  return rows;
}

}  // namespace

LabelledSet labelled_sample_town(const SampleOptions& opt, const std::string& name) {
  const SampleTown t = make_sample_town(opt);
  LabelledSet s;
  s.name = name;
  s.features = cloud_features(t.cloud.points, t.dtm);
  for (size_t i = 0; i < t.cloud.points.size(); ++i) s.labels.push_back(sample_label(t.cloud.classes[i], t.point_tags[i]));
  return s;
}

std::vector<SampleOptions> training_towns() {
  std::vector<SampleOptions> v;
  for (std::uint64_t seed = 101; seed <= 106; ++seed) v.push_back(town(seed));
  return v;
}

std::vector<SampleOptions> held_out_towns() {
  std::vector<SampleOptions> v;
  for (std::uint64_t seed = 201; seed <= 203; ++seed) v.push_back(town(seed));
  return v;
}

TrainingData training_data(const TrainingOptions& opt) {
  TrainingData d;
  for (const auto& o : training_towns())
    d.train.push_back(labelled_sample_town(o, "sample town " + std::to_string(o.seed)));
  for (const auto& o : held_out_towns())
    d.held_out.push_back(labelled_sample_town(o, "sample town " + std::to_string(o.seed)));
  if (!opt.cimahi_dir.empty() && std::filesystem::is_directory(opt.cimahi_dir)) add_cimahi(opt.cimahi_dir, d);
  else log::warn("classify: no Cimahi data at '" + opt.cimahi_dir + "': training on sample towns only");
  return d;
}

PointForest train_forest(const TrainingData& data, const TrainingOptions& opt) {
  std::mt19937_64 rng(opt.forest.seed);
  LabelledSet pool;
  for (const auto& set : data.train)
    for (int c = 0; c < kPointClassCount; ++c) {
      std::vector<size_t> rows;
      for (size_t i = 0; i < set.labels.size(); ++i)
        if (int(set.labels[i]) == c) rows.push_back(i);
      const LabelledSet part = subset(set, draw(rows, opt.max_per_class, rng), set.name);
      pool.features.values.insert(pool.features.values.end(), part.features.values.begin(), part.features.values.end());
      pool.labels.insert(pool.labels.end(), part.labels.begin(), part.labels.end());
    }
  pool.features.rows = pool.labels.size();
  log::info("classify: training on " + std::to_string(pool.labels.size()) + " points");
  PointForest f;
  f.train(pool.features, pool.labels, opt.forest);
  return f;
}

Evaluation evaluate(const PointForest& forest, const LabelledSet& set) {
  Evaluation e;
  e.name = set.name;
  const auto predicted = forest.predict(set.features);
  for (size_t i = 0; i < predicted.size(); ++i) ++e.confusion[int(set.labels[i])][int(predicted[i])];
  return e;
}

double Evaluation::precision(PointClass c) const {
  long called = 0;
  for (int t = 0; t < kPointClassCount; ++t) called += confusion[t][int(c)];
  return called ? double(confusion[int(c)][int(c)]) / called : kNaN;
}

double Evaluation::recall(PointClass c) const {
  const long n = support(c);
  return n ? double(confusion[int(c)][int(c)]) / n : kNaN;
}

long Evaluation::support(PointClass c) const {
  long n = 0;
  for (long v : confusion[int(c)]) n += v;
  return n;
}

std::string evaluation_table(const std::vector<Evaluation>& evals) {
  std::string out = "| held-out set | class | points | precision | recall |\n|---|---|---:|---:|---:|\n";
  char line[256];
  auto pct = [](double v) {
    char b[16];
    std::snprintf(b, sizeof b, "%.1f %%", 100 * v);
    return std::isfinite(v) ? std::string(b) : std::string("–");
  };
  for (const auto& e : evals)
    for (int c = 0; c < kPointClassCount; ++c) {
      const auto k = PointClass(c);
      if (e.support(k) == 0) continue;  // a class the set has no points of (Cimahi: ground, other)
      std::snprintf(line, sizeof line, "| %s | %s | %ld | %s | %s |\n", e.name.c_str(), to_string(k), e.support(k),
                    pct(e.precision(k)).c_str(), pct(e.recall(k)).c_str());
      out += line;
    }
  return out;
}

}  // namespace c3d
