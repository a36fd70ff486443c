#include "core/evaluate/ruler.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "core/geometry/geometry.h"

namespace c3d {
namespace {

constexpr double kMissM = 99.0;  // a point with no surface at all, as the judge counts it

double distance_to_segment(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

}  // namespace

RulerFigures ruler_figures(std::vector<double> d) {
  RulerFigures r;
  if (d.empty()) return r;
  for (double& v : d) v = std::isfinite(v) ? std::abs(v) : kMissM;
  std::sort(d.begin(), d.end());
  r.n = long(d.size());
  double sum2 = 0, within2 = 0;
  long within = 0, over03 = 0, over1 = 0;
  for (double v : d) {
    sum2 += v * v;
    if (v <= 1.0) within2 += v * v, ++within;
    over03 += v > 0.3;
    over1 += v > 1.0;
  }
  r.rmse = std::sqrt(sum2 / double(r.n));
  r.rmse_within_1m = within > 0 ? std::sqrt(within2 / double(within)) : 0;
  r.median = quantile_of_sorted(d, 0.5);
  r.p95 = quantile_of_sorted(d, 0.95);
  r.max = d.back();
  std::vector<double> dev(d.size());
  for (size_t i = 0; i < d.size(); ++i) dev[i] = std::abs(d[i] - r.median);
  std::sort(dev.begin(), dev.end());
  r.nmad = 1.4826 * quantile_of_sorted(dev, 0.5);
  r.share_over_0_3m = double(over03) / double(r.n);
  r.share_over_1m = double(over1) / double(r.n);
  return r;
}

namespace {

constexpr size_t kRulerBins = size_t(kMissM / kRulerBinM + 0.5) + 1;  // the last: the misses (and beyond)

double bin_value(size_t b) { return b + 1 == kRulerBins ? kMissM : (double(b) + 0.5) * kRulerBinM; }

// The value at `at` (a fractional rank) of counted values, as quantile_of_sorted reads it.
template <class ValueAtRank>
double interpolated(double at, long n, ValueAtRank value_at) {
  const long lo = long(std::floor(at)), hi = std::min(lo + 1, n - 1);
  const double a = value_at(lo);
  return a + (at - double(lo)) * (value_at(hi) - a);
}

}  // namespace

void RulerAccumulator::add(const std::vector<double>& distances) {
  if (bins_.empty()) bins_.assign(kRulerBins, 0);
  for (double v : distances) {
    v = std::isfinite(v) ? std::abs(v) : kMissM;
    ++n_;
    sum2_ += v * v;
    if (v <= 1.0) within2_ += v * v, ++within_;
    over03_ += v > 0.3;
    over1_ += v > 1.0;
    max_ = std::max(max_, v);
    ++bins_[std::min(kRulerBins - 1, size_t(v / kRulerBinM))];
  }
}

double RulerAccumulator::value_at_rank(long rank) const {
  long seen = 0;
  for (size_t b = 0; b < bins_.size(); ++b)
    if ((seen += long(bins_[b])) > rank) return std::min(max_, bin_value(b));
  return max_;
}

RulerFigures RulerAccumulator::figures() const {
  RulerFigures r;
  if (n_ == 0) return r;
  r.n = n_;
  r.rmse = std::sqrt(sum2_ / double(n_));
  r.rmse_within_1m = within_ > 0 ? std::sqrt(within2_ / double(within_)) : 0;
  r.max = max_;
  const double last = double(n_ - 1);
  auto at = [&](long k) { return value_at_rank(k); };
  r.median = interpolated(0.5 * last, n_, at);
  r.p95 = interpolated(0.95 * last, n_, at);
  // |value - median| per bin, in increasing order, for the median deviation.
  std::vector<std::pair<double, unsigned>> dev;
  for (size_t b = 0; b < bins_.size(); ++b)
    if (bins_[b]) dev.emplace_back(std::abs(std::min(max_, bin_value(b)) - r.median), bins_[b]);
  std::sort(dev.begin(), dev.end());
  auto dev_at = [&](long k) {
    long seen = 0;
    for (const auto& [d, c] : dev)
      if ((seen += long(c)) > k) return d;
    return dev.back().first;
  };
  r.nmad = 1.4826 * interpolated(0.5 * last, n_, dev_at);
  r.share_over_0_3m = double(over03_) / double(n_);
  r.share_over_1m = double(over1_) / double(n_);
  return r;
}

std::vector<char> near_rings(const std::vector<Vec3>& points, const std::vector<Ring3>& rings, double reach) {
  // Edges by grid cell of size `reach`: a point looks only at its own cell and the eight around it.
  std::map<std::pair<long, long>, std::vector<std::pair<Vec2, Vec2>>> cells;
  auto cell = [reach](double v) { return long(std::floor(v / reach)); };
  for (const auto& ring : rings)
    for (size_t i = 0; i < ring.size(); ++i) {
      const Vec2 a = ring[i].head<2>(), b = ring[(i + 1) % ring.size()].head<2>();
      for (long x = cell(std::min(a.x(), b.x())); x <= cell(std::max(a.x(), b.x())); ++x)
        for (long y = cell(std::min(a.y(), b.y())); y <= cell(std::max(a.y(), b.y())); ++y)
          cells[{x, y}].emplace_back(a, b);
    }
  std::vector<char> near(points.size(), 0);
  for (size_t k = 0; k < points.size(); ++k) {
    const Vec2 p = points[k].head<2>();
    for (long dx = -1; dx <= 1 && !near[k]; ++dx)
      for (long dy = -1; dy <= 1 && !near[k]; ++dy) {
        auto it = cells.find({cell(p.x()) + dx, cell(p.y()) + dy});
        if (it == cells.end()) continue;
        for (const auto& [a, b] : it->second)
          if (distance_to_segment(p, a, b) <= reach) {
            near[k] = 1;
            break;
          }
      }
  }
  return near;
}

}  // namespace c3d
