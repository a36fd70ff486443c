#include "core/classify/forest.h"

#include <opencv2/core.hpp>
#include <opencv2/ml.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>

#include "core/error.h"

namespace c3d {

// The trained trees laid flat for prediction: OpenCV's predict walks its
// general node and split records one sample at a time (~6 us a point for 40
// trees); this walks the same ordered splits (val <= c: left) and takes the
// same majority vote (ties to the lowest class index), in a fraction of it.
struct FlatNode {
  int var = -1;      // feature tested; -1: a leaf
  float at = 0;      // threshold: a value at or below it goes left
  int left = 0;      // node index, or the class index at a leaf
  int right = 0;
};

struct PointForest::Impl {
  cv::Ptr<cv::ml::RTrees> trees;
  std::vector<FlatNode> nodes;
  std::vector<int> roots;
  std::vector<float> labels;  // class label per class index

  void flatten() {
    const auto& cv_nodes = trees->getNodes();
    const auto& splits = trees->getSplits();
    nodes.assign(cv_nodes.size(), FlatNode{});
    labels.clear();
    for (size_t i = 0; i < cv_nodes.size(); ++i) {
      const auto& n = cv_nodes[i];
      if (n.split < 0) {
        nodes[i].left = n.classIdx;
        if (labels.size() <= size_t(n.classIdx)) labels.resize(size_t(n.classIdx) + 1, -1.0f);
        labels[size_t(n.classIdx)] = float(n.value);
      } else {
        nodes[i] = FlatNode{splits[size_t(n.split)].varIdx, splits[size_t(n.split)].c, n.left, n.right};
      }
    }
    roots = trees->getRoots();
  }

  // Classes of rows [begin, end): tree by tree over the block, so that one
  // tree's nodes stay in cache while its votes are cast.
  void vote(const FeatureTable& x, size_t begin, size_t end, std::vector<PointClass>& out) const {
    constexpr int kMaxClasses = 16;
    std::vector<std::array<int, kMaxClasses>> votes(end - begin, std::array<int, kMaxClasses>{});
    for (int root : roots)
      for (size_t i = begin; i < end; ++i) {
        const float* row = x.row(i);
        const FlatNode* n = &nodes[size_t(root)];
        while (n->var >= 0) n = &nodes[size_t(row[n->var] <= n->at ? n->left : n->right)];
        ++votes[i - begin][size_t(n->left & (kMaxClasses - 1))];
      }
    for (size_t i = begin; i < end; ++i) {
      const auto& v = votes[i - begin];
      int best = 0;
      for (int k = 1; k < int(labels.size()) && k < kMaxClasses; ++k)
        if (v[size_t(best)] < v[size_t(k)]) best = k;
      const int c = int(std::lround(labels[size_t(best)]));
      out[i] = c >= 0 && c < kPointClassCount ? PointClass(c) : PointClass::Other;
    }
  }
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
  f.impl_->flatten();
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
  impl_->flatten();
}

std::vector<PointClass> PointForest::predict(const FeatureTable& x) const {
  if (!trained()) throw std::logic_error("PointForest::predict: no trained model");
  constexpr size_t kBlock = 4096;
  std::vector<PointClass> out(x.rows, PointClass::Other);
  for (size_t at = 0; at < x.rows; at += kBlock) impl_->vote(x, at, std::min(x.rows, at + kBlock), out);
  return out;
}

std::vector<PointClass> PointForest::predict_by_opencv(const FeatureTable& x) const {
  if (!trained()) throw std::logic_error("PointForest::predict_by_opencv: no trained model");
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
