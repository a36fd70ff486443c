#include "cadastre/classify/cloud_evaluation.h"

#include <cmath>
#include <cstdio>

#include "core/classify/classify.h"
#include "core/error.h"
#include "core/io/dtm_io.h"
#include "core/io/point_io.h"

namespace c3d {
namespace {

// The predictions that count as each survey class.
bool called(SurveyClass c, int predicted) {
  switch (c) {
    case SurveyClass::Ground: return predicted == int(PointClass::Ground);
    case SurveyClass::Building: return predicted == int(PointClass::Roof) || predicted == int(PointClass::Wall);
    case SurveyClass::Vegetation: return predicted == int(PointClass::Other);
  }
  return false;
}

std::string share(double v) {
  char b[16];
  std::snprintf(b, sizeof b, std::isfinite(v) ? "%.3f" : "-", v);
  return b;
}

}  // namespace

std::optional<SurveyClass> survey_class(int code, const ClassMapping& classes) {
  if (classes.is_ground(code)) return SurveyClass::Ground;
  if (classes.is_roof(code) || classes.is_wall(code)) return SurveyClass::Building;
  if (code >= 3 && code <= 5) return SurveyClass::Vegetation;
  return std::nullopt;
}

const char* to_string(SurveyClass c) {
  switch (c) {
    case SurveyClass::Ground: return "ground";
    case SurveyClass::Building: return "building";
    case SurveyClass::Vegetation: return "vegetation";
  }
  return "?";
}

long CloudEvaluation::support(SurveyClass c) const {
  long n = 0;
  for (long v : confusion[size_t(c)]) n += v;
  return n;
}

double CloudEvaluation::recall(SurveyClass c) const {
  long hit = 0;
  for (int p = 0; p < kPointClassCount; ++p) hit += called(c, p) ? confusion[size_t(c)][size_t(p)] : 0;
  const long n = support(c);
  return n ? double(hit) / double(n) : kNaN;
}

double CloudEvaluation::precision(SurveyClass c) const {
  long hit = 0, all = 0;
  for (int t = 0; t < kSurveyClassCount; ++t)
    for (int p = 0; p < kPointClassCount; ++p)
      if (called(c, p)) all += confusion[size_t(t)][size_t(p)], hit += t == int(c) ? confusion[size_t(t)][size_t(p)] : 0;
  return all ? double(hit) / double(all) : kNaN;
}

double CloudEvaluation::accuracy() const {
  long hit = 0, all = 0;
  for (int t = 0; t < kSurveyClassCount; ++t)
    for (int p = 0; p < kPointClassCount; ++p) {
      all += confusion[size_t(t)][size_t(p)];
      hit += called(SurveyClass(t), p) ? confusion[size_t(t)][size_t(p)] : 0;
    }
  return all ? double(hit) / double(all) : kNaN;
}

CloudEvaluation evaluate_cloud(const PointForest& forest, const PointCloud& labelled, const ClassMapping& classes,
                               const Dtm* terrain) {
  CloudEvaluation e;
  Dtm found;
  if (terrain) {
    e.terrain_note = "terrain from " + terrain->source;
  } else {
    PointCloud unlabelled = labelled;
    unlabelled.classes.clear();  // as the survey would come: the terrain found without its ground class
    found = terrain_from_cloud(unlabelled, classes, &e.terrain_note);
  }
  const Classification c = classify_points(forest, labelled, terrain ? *terrain : found);
  for (size_t i = 0; i < labelled.points.size(); ++i) {
    const auto truth = i < labelled.classes.size() ? survey_class(labelled.classes[i], classes) : std::nullopt;
    if (!truth) ++e.unscored;
    else ++e.confusion[size_t(*truth)][size_t(c.classes[i])];
  }
  return e;
}

CloudEvaluation evaluate_cloud_file(const PointForest& forest, const std::string& cloud, const ClassMapping& classes,
                                    const std::string& dtm) {
  const PointCloud labelled = read_point_cloud(cloud);
  if (labelled.classes.empty()) throw InputError(cloud, "has no classes to evaluate against");
  if (dtm.empty()) return evaluate_cloud(forest, labelled, classes);
  const Dtm given = read_dtm(dtm);
  return evaluate_cloud(forest, labelled, classes, &given);
}

std::string cloud_evaluation_text(const CloudEvaluation& e, const std::string& name) {
  std::string out = name + ": " + e.terrain_note + "; accuracy " + share(e.accuracy()) + ", " +
                    std::to_string(e.unscored) + " points of other classes not scored\n\n" +
                    "| class | points | precision | recall |\n|---|---:|---:|---:|\n";
  for (int t = 0; t < kSurveyClassCount; ++t)
    out += "| " + std::string(to_string(SurveyClass(t))) + " | " + std::to_string(e.support(SurveyClass(t))) + " | " +
           share(e.precision(SurveyClass(t))) + " | " + share(e.recall(SurveyClass(t))) + " |\n";
  out += "\n| truth, called |";
  for (int p = 0; p < kPointClassCount; ++p) out += " " + std::string(to_string(PointClass(p))) + " |";
  out += "\n|---|---:|---:|---:|---:|\n";
  for (int t = 0; t < kSurveyClassCount; ++t) {
    out += "| " + std::string(to_string(SurveyClass(t))) + " |";
    for (int p = 0; p < kPointClassCount; ++p) out += " " + std::to_string(e.confusion[size_t(t)][size_t(p)]) + " |";
    out += "\n";
  }
  return out;
}

}  // namespace c3d
