#pragma once
// The point classifier: a Random Forest (OpenCV ml::RTrees) over the features
// of core/classify/features.h. OpenCV stays behind this header.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/classify/features.h"

namespace c3d {

// What the classifier tells apart; written to a cloud as the ClassMapping's codes
// (ground, roof, wall) and 1 ("unclassified") for other: vegetation and clutter.
enum class PointClass : std::uint8_t { Ground = 0, Roof = 1, Wall = 2, Other = 3 };
constexpr int kPointClassCount = 4;
const char* to_string(PointClass c);

struct ForestSettings {
  int trees = 20;          // 40 gained nothing left-one-tile-out; each tree costs ~0.1 us a point
  int max_depth = 14;
  int min_samples = 10;    // at a split: no leaf learns a handful of points by heart
  std::uint64_t seed = 1;  // OpenCV's random generator, for a reproducible forest
};

class PointForest {
 public:
  PointForest();
  ~PointForest();
  PointForest(PointForest&&) noexcept;
  PointForest& operator=(PointForest&&) noexcept;

  // Throws InputError(path, why) when the file is missing, unreadable or was
  // trained on other features.
  static PointForest load(const std::string& path);
  void save(const std::string& path) const;

  void train(const FeatureTable& features, const std::vector<PointClass>& labels, const ForestSettings& s);
  std::vector<PointClass> predict(const FeatureTable& features) const;
  // OpenCV's own prediction: the reference predict() is tested against.
  std::vector<PointClass> predict_by_opencv(const FeatureTable& features) const;
  // Each feature's share of the forest's decisions (OpenCV's variable importance).
  std::vector<double> importance() const;
  bool trained() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace c3d
