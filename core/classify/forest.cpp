#include "core/classify/forest.h"

#include <opencv2/core.hpp>
#include <opencv2/ml.hpp>

#include <filesystem>

#include "core/error.h"

namespace c3d {

struct PointForest::Impl {
  cv::Ptr<cv::ml::RTrees> trees;
};

const char* to_string(PointClass c) {
  switch (c) {
    case PointClass::Ground: return "ground";
    case PointClass::Roof: return "roof";
    case PointClass::Wall: return "wall";
    case PointClass::Other: return "other";
  }
  return "?";
}

PointForest::PointForest() : impl_(std::make_unique<Impl>()) {}
PointForest::~PointForest() = default;
PointForest::PointForest(PointForest&&) noexcept = default;
PointForest& PointForest::operator=(PointForest&&) noexcept = default;

bool PointForest::trained() const { return impl_->trees && impl_->trees->isTrained(); }

PointForest PointForest::load(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) throw InputError(path, "classifier model not found");
  PointForest f;
  try {
    f.impl_->trees = cv::ml::RTrees::load(path);
  } catch (const cv::Exception& e) {
    throw InputError(path, "not a classifier model OpenCV can read (" + e.msg + ")");
  }
  if (!f.trained()) throw InputError(path, "not a trained classifier model");
  if (f.impl_->trees->getVarCount() != kFeatureCount)
    throw InputError(path, "model expects " + std::to_string(f.impl_->trees->getVarCount()) +
                               " features, this program computes " + std::to_string(kFeatureCount) +
                               " (retrain it: scripts/train_classifier.sh)");
  return f;
}

void PointForest::save(const std::string& path) const {
  if (!trained()) throw std::logic_error("PointForest::save: no trained model");
  try {
    impl_->trees->save(path);
  } catch (const cv::Exception& e) {
    throw InputError(path, "cannot write the model (" + e.msg + ")");
  }
}

void PointForest::train(const FeatureTable& x, const std::vector<PointClass>& y, const ForestSettings& s) {
  cv::Mat samples(int(x.rows), kFeatureCount, CV_32F, const_cast<float*>(x.values.data()));
  cv::Mat responses(int(y.size()), 1, CV_32S);
  for (size_t i = 0; i < y.size(); ++i) responses.at<int>(int(i)) = int(y[i]);
  cv::setRNGSeed(int(s.seed));
  auto t = cv::ml::RTrees::create();
  t->setMaxDepth(s.max_depth);
  t->setMinSampleCount(s.min_samples);
  t->setActiveVarCount(0);  // sqrt of the feature count per split
  t->setCalculateVarImportance(true);
  t->setTermCriteria(cv::TermCriteria(cv::TermCriteria::MAX_ITER, s.trees, 0));
  t->train(cv::ml::TrainData::create(samples, cv::ml::ROW_SAMPLE, responses));
  impl_->trees = t;
}

std::vector<PointClass> PointForest::predict(const FeatureTable& x) const {
  if (!trained()) throw std::logic_error("PointForest::predict: no trained model");
  std::vector<PointClass> out(x.rows, PointClass::Other);
  if (x.rows == 0) return out;
  cv::Mat samples(int(x.rows), kFeatureCount, CV_32F, const_cast<float*>(x.values.data()));
  cv::Mat result;
  impl_->trees->predict(samples, result);
  for (size_t i = 0; i < x.rows; ++i) {
    const int c = int(std::lround(result.at<float>(int(i))));
    out[i] = c >= 0 && c < kPointClassCount ? PointClass(c) : PointClass::Other;
  }
  return out;
}

std::vector<double> PointForest::importance() const {
  std::vector<double> out(kFeatureCount, 0.0);
  if (!trained()) return out;
  cv::Mat imp = impl_->trees->getVarImportance();
  if (imp.empty()) return out;
  imp.convertTo(imp, CV_64F);
  double sum = cv::sum(imp)[0];
  for (int i = 0; i < kFeatureCount && i < int(imp.total()); ++i) out[i] = sum > 0 ? imp.at<double>(i) / sum : 0;
  return out;
}

}  // namespace c3d
