#pragma once
// A labelled cloud (a survey's own ASPRS classes) judged as if it came
// unclassified: its classes set aside, the terrain found without them, every
// point classified, and the result scored against the classes it had
// (`cadastre3d classify --cloud FILE --evaluate`, issue 51).
#include <array>
#include <optional>
#include <string>

#include "core/classify/forest.h"
#include "core/types.h"

namespace c3d {

// What a labelled point is: the mapping's ground codes; its roof and wall
// codes (ASPRS has one building class for both); vegetation, ASPRS 3-5, which
// the forest calls other. Points of any other code (unclassified, water,
// noise) are not scored.
enum class SurveyClass { Ground, Building, Vegetation };
constexpr int kSurveyClassCount = 3;
const char* to_string(SurveyClass c);
// The survey class of a class code under the mapping; none for codes not scored.
std::optional<SurveyClass> survey_class(int code, const ClassMapping& classes);

struct CloudEvaluation {
  std::array<std::array<long, kPointClassCount>, kSurveyClassCount> confusion{};  // [truth][predicted]
  long unscored = 0;
  std::string terrain_note;
  // Building counts roof and wall predictions, vegetation other. NaN when
  // nothing was called so, or no point is so.
  double precision(SurveyClass c) const;
  double recall(SurveyClass c) const;
  long support(SurveyClass c) const;
  double accuracy() const;  // share of the scored points called what they are
};

// `terrain`: a DTM given with the survey; none: found from the points alone.
CloudEvaluation evaluate_cloud(const PointForest& forest, const PointCloud& labelled, const ClassMapping& classes,
                               const Dtm* terrain = nullptr);

// The same for a labelled file (LAS, LAZ, ...) and a DTM file (empty: none).
// Throws InputError naming a file without classes.
CloudEvaluation evaluate_cloud_file(const PointForest& forest, const std::string& cloud, const ClassMapping& classes,
                                    const std::string& dtm);

// The scores and the confusion matrix as text for the terminal (Markdown tables).
std::string cloud_evaluation_text(const CloudEvaluation& e, const std::string& name);

}  // namespace c3d
