#include "core/reconstruct/segment/coplanar.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

#include "core/reconstruct/planes/planes.h"

namespace c3d {
namespace {

constexpr double kCoplanarDeg = 6.0;  // planes nearer parallel than this may be one plane

bool coplanar(const PlaneFit& a, const PlaneFit& b, double tol) {
  const double c = std::clamp(std::abs(a.plane.n.dot(b.plane.n)), 0.0, 1.0);
  // The angle by its cosine, clear of the threshold; acos only near it (the same answer, cheaper).
  static const double cos_limit = std::cos(kCoplanarDeg * M_PI / 180.0);
  if (c < cos_limit - 1e-9) return false;
  if (c <= cos_limit + 1e-9 && std::acos(c) * 180.0 / M_PI > kCoplanarDeg) return false;
  return !(std::abs(a.plane.distance(b.centroid)) > tol || std::abs(b.plane.distance(a.centroid)) > tol);
}

// Which pairs are known not to merge: each component (by a stable id) has the
// merge step of its last refit, each row the step it was last found clean at.
struct MergeLog {
  std::vector<int> id;                       // per position: the component's id
  std::vector<int> pos;                      // per id: its position, -1 once merged away
  std::vector<long> changed, clean;          // per id: step of the last refit / clean row (-1: never)
  std::vector<std::pair<long, int>> refits;  // (step, id), steps ascending
  long step = 0;

  explicit MergeLog(size_t n) : id(n), pos(n), changed(n, -1), clean(n, -1) {
    for (size_t k = 0; k < n; ++k) id[k] = pos[k] = int(k);
  }
  // Positions after k whose pair with k needs a test, ascending.
  std::vector<size_t> to_test(size_t k) const {
    std::vector<size_t> out;
    const int row = id[k];
    if (clean[size_t(row)] < 0 || changed[size_t(row)] > clean[size_t(row)]) {
      for (size_t l = k + 1; l < id.size(); ++l) out.push_back(l);
      return out;
    }
    for (auto it = refits.rbegin(); it != refits.rend() && it->first > clean[size_t(row)]; ++it) {
      const int p = pos[size_t(it->second)];
      if (p > int(k)) out.push_back(size_t(p));
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }
  void merged(size_t i, size_t j) {
    ++step;
    changed[size_t(id[i])] = step;
    refits.emplace_back(step, id[i]);
    pos[size_t(id[j])] = -1;
    id.erase(id.begin() + long(j));
    for (size_t k = j; k < id.size(); ++k) pos[size_t(id[k])] = int(k);
  }
};

}  // namespace

void merge_coplanar(const std::vector<Vec3>& pts, std::vector<RoofComponent>& comps, double tol) {
  MergeLog log(comps.size());
  for (;;) {
    std::optional<std::pair<size_t, size_t>> pair;
    for (size_t i = 0; i < comps.size() && !pair; ++i) {
      for (size_t j : log.to_test(i))
        if (coplanar(comps[i].fit, comps[j].fit, tol)) {
          pair = std::make_pair(i, j);
          break;
        }
      if (!pair) log.clean[size_t(log.id[i])] = log.step;
    }
    if (!pair) return;
    const auto [i, j] = *pair;
    auto& dst = comps[i].points;
    dst.insert(dst.end(), comps[j].points.begin(), comps[j].points.end());
    comps[i].fit = fit_plane_robust(pts, dst, tol);
    comps.erase(comps.begin() + long(j));
    log.merged(i, j);
  }
}

}  // namespace c3d
