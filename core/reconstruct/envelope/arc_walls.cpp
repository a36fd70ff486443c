#include "core/reconstruct/envelope/arc_walls.h"

#include <cmath>
#include <map>

namespace c3d::envelope {
namespace {

// Walls seen under several chords of one arc, taken as one: the
// support-weighted median of their values, all their support, and the rms
// of all their points about their walls.
struct Pool {
  std::vector<Weighted> values;
  int support = 0;
  double ss = 0;
  void add(double value, int n, double rms) {
    values.push_back({value, double(n)});
    support += n;
    ss += n * rms * rms;
  }
  double median() const { return weighted_median(values); }
  double rms() const { return std::sqrt(ss / support); }
};

}  // namespace

void pool_arcs(std::vector<OutlineEdge>& edges, double vertex_tolerance) {
  std::map<int, std::vector<OutlineEdge*>> arcs;
  for (OutlineEdge& e : edges)
    if (e.arc >= 0 && !e.party) arcs[e.arc].push_back(&e);
  for (auto& [id, chords] : arcs) {
    Pool overhang;
    std::vector<Weighted> outside;
    for (const OutlineEdge* e : chords)
      if (e->evidence == WallEvidence::Measured) {
        overhang.add(e->overhang, e->support, e->rms);
        outside.push_back({e->outside, double(e->support)});
      }
    if (overhang.values.empty()) continue;
    // As a straight wall's (measure_own_walls): a wall seen outside the arc
    // stands at it, that distance part of its error.
    const double median = overhang.median(), rms = overhang.rms();
    const double sigma =
        std::hypot(rms / std::sqrt(double(overhang.support)), vertex_tolerance / std::sqrt(3.0)) +
        weighted_median(outside);
    for (OutlineEdge* e : chords) {
      e->overhang = median, e->evidence = WallEvidence::Measured;
      e->support = overhang.support, e->rms = rms;
      e->sigma = 0;
      e->sigma_shared = sigma;
    }
  }
}

void pool_arc_fits(const Ring2& ring, const std::vector<int>& arc, std::vector<WallFit>& fits) {
  std::map<int, std::vector<size_t>> chords;
  for (size_t i = 0; i < ring.size(); ++i)
    if (arc[i] >= 0) chords[arc[i]].push_back(i);
  for (const auto& [id, edges] : chords) {
    Pool offset;
    for (size_t i : edges)
      if (fits[i].found) offset.add(fits[i].offset, fits[i].support, fits[i].rms);
    if (offset.values.empty()) continue;
    const WallFit pooled{true, offset.median(), offset.support, offset.rms()};
    for (size_t i : edges) fits[i] = pooled;
  }
}

}  // namespace c3d::envelope
