#include "core/reconstruct/envelope/arc_walls.h"

#include <cmath>
#include <map>

namespace c3d::envelope {

void pool_arcs(std::vector<OutlineEdge>& edges, double vertex_tolerance) {
  std::map<int, std::vector<OutlineEdge*>> arcs;
  for (OutlineEdge& e : edges)
    if (e.arc >= 0 && !e.party) arcs[e.arc].push_back(&e);
  for (auto& [id, chords] : arcs) {
    std::vector<Weighted> seen, outside;
    int support = 0;
    double ss = 0;
    for (const OutlineEdge* e : chords)
      if (e->evidence == WallEvidence::Measured) {
        seen.push_back({e->overhang, double(e->support)});
        outside.push_back({e->outside, double(e->support)});
        support += e->support;
        ss += e->support * e->rms * e->rms;
      }
    if (seen.empty()) continue;
    const double overhang = weighted_median(seen), rms = std::sqrt(ss / support);
    // As a straight wall's (measure_own_walls): a wall seen outside the arc
    // stands at it, that distance part of its error.
    const double sigma = std::hypot(rms / std::sqrt(double(support)), vertex_tolerance / std::sqrt(3.0)) +
                         weighted_median(outside);
    for (OutlineEdge* e : chords) {
      e->overhang = overhang, e->evidence = WallEvidence::Measured;
      e->support = support, e->rms = rms;
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
    std::vector<Weighted> found;
    WallFit pooled;
    double ss = 0;
    for (size_t i : edges)
      if (fits[i].found) {
        found.push_back({fits[i].offset, double(fits[i].support)});
        pooled.support += fits[i].support;
        ss += fits[i].support * fits[i].rms * fits[i].rms;
      }
    if (found.empty()) continue;
    pooled.found = true;
    pooled.offset = weighted_median(found);
    pooled.rms = std::sqrt(ss / pooled.support);
    for (size_t i : edges) fits[i] = pooled;
  }
}

}  // namespace c3d::envelope
