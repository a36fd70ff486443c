#pragma once
// The batch-wide rulers (issue 34), figure for figure as the shared judge
// (tools/eval_cityjson.py) reads them from the CityJSON: every roof point
// inside the parcels against the nearest roof of any building; the wall
// points of modelled buildings (within kFootprintReachM in plan of a
// footprint edge) against the nearest wall, with the share so measured.
#include <vector>

#include "core/types.h"

namespace c3d {

constexpr double kFootprintReachM = 1.5;  // a wall point this near a footprint edge is that building's

struct RulerFigures {
  long n = 0;
  double rmse = 0, median = 0, nmad = 0, p95 = 0, max = 0;
  double rmse_within_1m = 0;   // of the points within 1 m: the fit where a model stands
  double share_over_0_3m = 0, share_over_1m = 0;  // completeness: points no surface serves
};

// Figures of unsigned distances (NaN: no surface at all, counted as a miss at 99 m as the judge does).
RulerFigures ruler_figures(std::vector<double> distances);

// Per point: within `reach` in plan of an edge of any of the rings.
std::vector<char> near_rings(const std::vector<Vec3>& points, const std::vector<Ring3>& rings, double reach);

}  // namespace c3d

namespace c3d {

// The rulers with bounded memory: distances fed in parts (a chunk of parcels at
// a time) give ruler_figures of all of them. n, rmse, rmse_within_1m, max and
// the shares are exact; median, p95 and nmad are read from a histogram of
// kRulerBinM bins up to the 99 m miss value: median and p95 within half a bin
// (0.05 mm) of ruler_figures', nmad within 1.4826 x 0.1 mm (0.15 mm).
constexpr double kRulerBinM = 1e-4;

class RulerAccumulator {
 public:
  void add(const std::vector<double>& distances);
  RulerFigures figures() const;

 private:
  double value_at_rank(long rank) const;
  std::vector<unsigned> bins_;  // counts per kRulerBinM bin, sized on first use (4 MB)
  long n_ = 0, within_ = 0, over03_ = 0, over1_ = 0;
  double sum2_ = 0, within2_ = 0, max_ = 0;
};

}  // namespace c3d
