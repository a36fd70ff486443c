#include "cadastre/classify/training.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <random>

#include "cadastre/batch/tiles.h"
#include "cadastre/parcels.h"
#include "core/classify/classify.h"
#include "core/error.h"
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
  all.features = cloud_features(cloud, dtm);
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

constexpr double kWallVerticality = 0.7;  // a building point's 1.2 m neighbourhood: normal within ~45 deg of level
constexpr int kVerticality1_2m = 1 * kFeaturesPerScale + 3;
constexpr int kMultipleReturns = 8;  // per scale

// The forest's label for a labelled point: building as roof, or wall where
// its neighbourhood is vertical (ASPRS has one class for both).
PointClass survey_label(SurveyClass c, const float* features) {
  if (c == SurveyClass::Ground) return PointClass::Ground;
  if (c == SurveyClass::Vegetation) return PointClass::Other;
  return features[kVerticality1_2m] > kWallVerticality ? PointClass::Wall : PointClass::Roof;
}

SurveyClass survey_class(PointClass c) {
  return c == PointClass::Ground ? SurveyClass::Ground : c == PointClass::Other ? SurveyClass::Vegetation
                                                                                : SurveyClass::Building;
}

// The set as a survey without return fields would give it: every return
// feature unknown. Trained beside the set itself, so a forest learns real
// surveys both with and without them.
LabelledSet without_returns(LabelledSet s) {
  constexpr int kNotLastReturn = kFeatureCount - 1;
  for (size_t i = 0; i < s.features.rows; ++i) {
    float* f = s.features.values.data() + i * kFeatureCount;
    for (int k = 0; k < kScaleCount; ++k) f[k * kFeaturesPerScale + kMultipleReturns] = kUnknownReturns;
    f[kNotLastReturn] = kUnknownReturns;
  }
  s.name += ", returns hidden";
  return s;
}

bool has_returns(const LabelledSet& s) {
  return s.features.rows > 0 && s.features.row(0)[kFeatureCount - 1] != kUnknownReturns;
}

// Every survey of `from` but the one at `skip` (none: SIZE_MAX), with its
// returns and without them.
void append_surveys(std::vector<LabelledSet>& to, const std::vector<LabelledSet>& from, size_t skip = SIZE_MAX) {
  for (size_t i = 0; i < from.size(); ++i) {
    if (i == skip) continue;
    to.push_back(from[i]);
    if (has_returns(from[i])) to.push_back(without_returns(from[i]));
  }
}

SurveyScore score(const PointForest& forest, const LabelledSet& set) {
  SurveyScore s;
  s.name = set.name;
  const auto predicted = forest.predict(set.features);
  for (size_t i = 0; i < predicted.size(); ++i)
    ++s.scores.confusion[size_t(survey_class(set.labels[i]))][size_t(predicted[i])];
  return s;
}

}  // namespace

std::vector<std::string> labelled_survey_files(const std::string& dir) {
  return dir.empty() ? std::vector<std::string>{} : expand_point_files({dir});
}

LabelledSet labelled_survey(const std::string& path, const ClassMapping& classes) {
  PointCloud cloud = read_point_cloud(path);
  if (cloud.classes.empty()) throw InputError(path, "has no classes to train on");
  const std::vector<std::uint8_t> codes = std::move(cloud.classes);
  cloud.classes.clear();  // the terrain as an unclassified survey gets it
  const Dtm terrain = terrain_from_cloud(cloud, classes, nullptr);
  const FeatureTable all = cloud_features(cloud, terrain);
  LabelledSet s;
  s.name = std::filesystem::path(path).stem().string();
  s.features.values.reserve(all.values.size());
  for (size_t i = 0; i < codes.size(); ++i) {
    const auto truth = survey_class(codes[i], classes);
    if (!truth) continue;
    s.features.values.insert(s.features.values.end(), all.row(i), all.row(i) + kFeatureCount);
    s.labels.push_back(survey_label(*truth, all.row(i)));
  }
  s.features.rows = s.labels.size();
  return s;
}

std::vector<LabelledSet> labelled_surveys(const std::string& dir, const ClassMapping& classes) {
  std::vector<LabelledSet> surveys;
  for (const auto& f : labelled_survey_files(dir)) surveys.push_back(labelled_survey(f, classes));
  return surveys;
}

std::vector<SurveyScore> leave_one_survey_out(const TrainingOptions& opt, const ClassMapping& classes) {
  const std::vector<LabelledSet> surveys = labelled_surveys(opt.labelled_dir, classes);
  TrainingOptions own = opt;
  own.labelled_dir.clear();
  const TrainingData base = training_data(own);
  std::vector<SurveyScore> out;
  for (size_t k = 0; k < surveys.size(); ++k) {
    TrainingData d;
    d.train = base.train;
    append_surveys(d.train, surveys, k);
    const PointForest forest = train_forest(d, opt);
    out.push_back(score(forest, surveys[k]));
    if (has_returns(surveys[k])) out.push_back(score(forest, without_returns(surveys[k])));
  }
  return out;
}

std::string survey_scores_table(const std::vector<SurveyScore>& scores) {
  std::string out = "| left out | accuracy | ground P / R | building P / R | vegetation P / R |\n|---|---|---|---|---|\n";
  char line[256];
  for (const auto& s : scores) {
    const auto& e = s.scores;
    auto pr = [&](SurveyClass c) {
      char b[32];
      std::snprintf(b, sizeof b, "%.3f / %.3f", e.precision(c), e.recall(c));
      return std::string(b);
    };
    std::snprintf(line, sizeof line, "| %s | %.3f | %s | %s | %s |\n", s.name.c_str(), e.accuracy(),
                  pr(SurveyClass::Ground).c_str(), pr(SurveyClass::Building).c_str(), pr(SurveyClass::Vegetation).c_str());
    out += line;
  }
  return out;
}

LabelledSet labelled_sample_town(const SampleOptions& opt, const std::string& name) {
  const SampleTown t = make_sample_town(opt);
  LabelledSet s;
  s.name = name;
  s.features = cloud_features(t.cloud, t.dtm);
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
  append_surveys(d.train, labelled_surveys(opt.labelled_dir, ClassMapping{}));
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
