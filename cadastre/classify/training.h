#pragma once
// Training and judging the point classifier on the labelled data the project
// has: sample towns with trees (core/synthetic, exact labels) and the Cimahi
// survey (roof and wall classes). Held out, never trained on: whole sample towns
// (their own seeds) and every third Cimahi parcel.
#include <array>
#include <string>
#include <vector>

#include "core/classify/forest.h"
#include "core/synthetic/sample_town.h"

namespace c3d {

struct LabelledSet {
  std::string name;
  FeatureTable features;
  std::vector<PointClass> labels;
};

// The points of a sample town with their exact classes: ground, roof, wall, and
// other for trees, roof clutter and outliers; features over the town's terrain.
LabelledSet labelled_sample_town(const SampleOptions& opt, const std::string& name);

// The sample towns trained on and held out: three kinds of survey (airborne with
// sparse facades, UAV with handheld walls, dense UAV with sparse walls).
std::vector<SampleOptions> training_towns();
std::vector<SampleOptions> held_out_towns();

struct TrainingOptions {
  std::string cimahi_dir;  // empty or missing: sample towns only
  ForestSettings forest;
  long max_per_class = 12000;  // training points per class and source, drawn with the forest's seed
};

struct TrainingData {
  std::vector<LabelledSet> train, held_out;
};
TrainingData training_data(const TrainingOptions& opt);

// Confusion counts [truth][predicted] on one held-out set.
struct Evaluation {
  std::string name;
  std::array<std::array<long, kPointClassCount>, kPointClassCount> confusion{};
  double precision(PointClass c) const;  // NaN when nothing was called c
  double recall(PointClass c) const;     // NaN when no point is c
  long support(PointClass c) const;
};
Evaluation evaluate(const PointForest& forest, const LabelledSet& set);

// Trains on data.train (balanced per class and source).
PointForest train_forest(const TrainingData& data, const TrainingOptions& opt);

// Markdown table: per set and class, precision, recall and points.
std::string evaluation_table(const std::vector<Evaluation>& evals);

}  // namespace c3d
