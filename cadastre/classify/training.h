#pragma once
// Training and judging the point classifier on the labelled data the project
// has: sample towns with trees (core/synthetic, exact labels) and the Cimahi
// survey (roof and wall classes). Held out, never trained on: whole sample towns
// (their own seeds) and every third Cimahi parcel.
#include <array>
#include <string>
#include <vector>

#include "cadastre/classify/cloud_evaluation.h"
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
  std::string cimahi_dir;    // empty or missing: sample towns only
  std::string labelled_dir;  // labelled surveys (LAS/LAZ with ASPRS classes); empty: none
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

// A labelled airborne survey (ASPRS classes) as training points: features over
// the terrain found without its classes (as an unclassified survey is
// classified); ground; building as roof, or wall where its neighbourhood is
// vertical (ASPRS has one class for both); vegetation (3-5) as other. Points of
// other codes are left out.
LabelledSet labelled_survey(const std::string& path, const ClassMapping& classes);
// The point files of a folder, sorted (none for ""); InputError for a folder that is not there.
std::vector<std::string> labelled_survey_files(const std::string& dir);
// labelled_survey of each file of the folder (none for "").
std::vector<LabelledSet> labelled_surveys(const std::string& dir, const ClassMapping& classes);

// Trains on data.train (balanced per class and source).
PointForest train_forest(const TrainingData& data, const TrainingOptions& opt);

// Leave one tile out over the labelled surveys of opt.labelled_dir: for each,
// a forest trained on the project's own sources and every other survey, scored
// on the one left out (ground, building, vegetation; cloud_evaluation.h).
struct SurveyScore {
  std::string name;
  CloudEvaluation scores;
};
std::vector<SurveyScore> leave_one_survey_out(const TrainingOptions& opt, const ClassMapping& classes);
std::string survey_scores_table(const std::vector<SurveyScore>& scores);

// Markdown table: per set and class, precision, recall and points.
std::string evaluation_table(const std::vector<Evaluation>& evals);

}  // namespace c3d
