#include "core/reconstruct/roof/roof.h"

#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_types.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <optional>

#include "core/geometry/geometry.h"
#include "core/geometry/label_grid.h"
#include "core/geometry/polygon_ops.h"
#include "core/reconstruct/roof/roof_constants.h"
#include "core/reconstruct/roof/roof_snap.h"
#include "core/reconstruct/roof/roof_tiles.h"

namespace c3d {

using namespace roof;

namespace {

double polyline_length(const std::vector<std::vector<Vec2>>& lines) {
  double len = 0;
  for (const auto& l : lines)
    for (size_t i = 1; i < l.size(); ++i) len += (l[i] - l[i - 1]).norm();
  return len;
}

// Each region's box and near zone (poly::NearZone at kSharedTol), built on
// first use (the regions must not change meanwhile): the same shared
// boundaries as poly::shared_boundary without buffering a region once per
// pair, nor walking its vertices once per neighbour for its box.
class ZoneCache {
 public:
  explicit ZoneCache(const std::vector<MultiPolygon2>& regions)
      : regions_(regions), zones_(regions.size()), boxes_(regions.size()) {}
  double shared_length(const MultiPolygon2& a, size_t j) {
    if (!zones_[j]) zones_[j] = std::make_unique<poly::NearZone>(regions_[j], kSharedTol);
    return polyline_length(zones_[j]->shared_with(a));
  }
  const Box& box(size_t j) {
    if (!boxes_[j]) boxes_[j] = box_of(regions_[j]);
    return *boxes_[j];
  }

 private:
  const std::vector<MultiPolygon2>& regions_;
  std::vector<std::unique_ptr<poly::NearZone>> zones_;
  std::vector<std::optional<Box>> boxes_;
};

// Label grid -> one region per component.
std::vector<MultiPolygon2> label_regions(const RoofPartitionInput& in) {
  size_t k = in.components.size();
  pcl::PointCloud<pcl::PointXY>::Ptr cloud(new pcl::PointCloud<pcl::PointXY>);
  for (const auto& p : in.points) cloud->push_back(pcl::PointXY{float(p.x()), float(p.y())});
  pcl::KdTreeFLANN<pcl::PointXY> tree;
  tree.setInputCloud(cloud);
  std::map<int, int> slot;
  for (size_t i = 0; i < k; ++i) slot[in.components[i]] = int(i);

  Vec2 lo = in.outline.outer[0], hi = lo;
  for (const auto& p : in.outline.outer) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  lo -= Vec2(in.cell, in.cell);
  hi += Vec2(in.cell, in.cell);
  int nx = int(std::ceil((hi.x() - lo.x()) / in.cell)), ny = int(std::ceil((hi.y() - lo.y()) / in.cell));
  // Label of every cell: the majority of its 3 nearest points.
  std::vector<int> grid(size_t(nx) * ny, -1);
  std::vector<int> nn(3);
  std::vector<float> d2(3);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      pcl::PointXY c{float(lo.x() + (i + 0.5) * in.cell), float(lo.y() + (j + 0.5) * in.cell)};
      int found = tree.nearestKSearch(c, 3, nn, d2);
      if (found == 0) continue;
      int best = slot[in.labels[nn[0]]];
      if (found == 3 && in.labels[nn[1]] == in.labels[nn[2]]) best = slot[in.labels[nn[1]]];
      grid[size_t(j) * nx + i] = best;
    }
  // A 3x3 majority filter removes single-cell islands, which would otherwise
  // become many tiny orphan polygons to reassign.
  std::vector<int> smooth = grid;
  for (int j = 1; j + 1 < ny; ++j)
    for (int i = 1; i + 1 < nx; ++i) {
      std::map<int, int> votes;
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) ++votes[grid[size_t(j + dj) * nx + i + di]];
      for (auto& [lab, v] : votes)
        if (v >= kSmoothMajority) smooth[size_t(j) * nx + i] = lab;
    }
  // Runs too small to keep go to a neighbour here, on the cells, where shared
  // lengths are whole cell edges: fix_coverage is left the outline's slivers.
  const MultiPolygon2 outline{in.outline};
  LabelGrid labels{nx, ny, lo, in.cell, std::move(smooth)};
  std::vector<char> inside(labels.labels.size());
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      inside[size_t(j) * nx + i] = poly::covers(outline, lo + in.cell * Vec2(i + 0.5, j + 0.5));
  sieve(labels, inside, int(std::ceil(kMinCoverPart / (in.cell * in.cell))));
  std::vector<MultiPolygon2> regions = polygonize(labels, k);
  for (auto& r : regions) r = poly::intersect(r, outline);
  return regions;
}

// The region `o` shares the longest boundary with (lengths within kLengthTie
// are equal: the lower index wins, so last digits decide nothing); failing
// that, one it touches at a corner; -1 if none.
int best_neighbour(const Polygon2& o, const std::vector<MultiPolygon2>& regions, ZoneCache& zones) {
  int best = -1;
  double best_len = 0;
  Box ob = box_of({o});
  for (size_t i = 0; i < regions.size(); ++i) {
    if (!ob.near(zones.box(i), kBoxMargin)) continue;
    double len = zones.shared_length({o}, i);
    if (len > best_len + kLengthTie) best_len = len, best = int(i);
  }
  for (size_t i = 0; best < 0 && i < regions.size(); ++i)
    if (ob.near(zones.box(i), kCornerTouchTol) && !poly::shared_boundary({o}, regions[i], kCornerTouchTol).empty())
      best = int(i);
  return best;
}

// Every piece of the outline belongs to exactly one region: gaps and small
// parts, neighbouring ones united, go whole to the region sharing the longest
// boundary with them. All are measured against the regions as they stand and
// given at the end, so no choice depends on the order of the others.
void fix_coverage(const Polygon2& outline, std::vector<MultiPolygon2>& regions, double min_part) {
  for (auto& r : regions) {
    MultiPolygon2 keep;
    for (auto& part : r)
      if (area(part) >= min_part) keep.push_back(part);
    r = keep;
  }
  const MultiPolygon2 orphans = poly::subtract({outline}, poly::unite_all(regions));
  ZoneCache zones(regions);
  std::vector<MultiPolygon2> gifts(regions.size());
  for (const auto& o : orphans) {
    if (area(o) < kOrphanDust) continue;
    const int best = best_neighbour(o, regions, zones);
    if (best >= 0) gifts[size_t(best)].push_back(o);
  }
  for (size_t i = 0; i < regions.size(); ++i)
    if (!gifts[i].empty()) regions[i] = poly::unite_all({regions[i], gifts[i]});
}

struct CutLine {
  Vec2 point, dir;
};

// Ridge / hip / valley: where the two planes meet near their shared boundary.
std::optional<CutLine> intersection_cut(const Plane& a, const Plane& b,
                                        const std::vector<Vec2>& boundary) {
  auto line = intersect(a, b, kMinPlaneAngleDeg);
  if (!line) return std::nullopt;
  Vec2 dir = line->dir.head<2>();
  if (dir.norm() < kMinPlanDir) return std::nullopt;
  dir.normalize();
  Vec2 p = line->point.head<2>();
  Vec2 n(-dir.y(), dir.x());
  double dist = 0, dz = 0;
  for (const auto& v : boundary) {
    dist += std::abs(n.dot(v - p));
    dz += std::abs(a.z_at(v.x(), v.y()) - b.z_at(v.x(), v.y()));
  }
  dist /= boundary.size();
  dz /= boundary.size();
  if (dist > kMaxCutDistance || dz > kMaxCutHeightGap) return std::nullopt;
  return CutLine{p, dir};
}

// Least-squares line through points, with the RMS of their distances to it.
std::pair<CutLine, double> fit_line(const std::vector<Vec2>& pts) {
  Vec2 c = Vec2::Zero();
  for (const auto& v : pts) c += v;
  c /= double(pts.size());
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (const auto& v : pts) cov += (v - c) * (v - c).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(cov);
  return {CutLine{c, es.eigenvectors().col(1)}, std::sqrt(std::max(es.eigenvalues()(0), 0.0) / double(pts.size()))};
}

// Step between roof levels: the straight line through the boundary.
std::optional<CutLine> step_cut(const std::vector<Vec2>& boundary) {
  if (boundary.size() < 2) return std::nullopt;
  auto [line, rms] = fit_line(boundary);
  if (rms > kMaxStepRms) return std::nullopt;
  return line;
}

// A staircase polyline as straight legs: its corners found by Douglas-Peucker,
// each leg the least-squares line through the stretch between two corners,
// neighbouring legs meeting where their lines cross.
std::vector<Vec2> straight_legs(const std::vector<Vec2>& stairs, double tolerance) {
  const std::vector<Vec2> corners = poly::simplify_line(stairs, tolerance);
  std::vector<CutLine> legs;
  size_t from = 0;
  for (size_t c = 1; c < corners.size(); ++c) {
    size_t to = from + 1;  // Douglas-Peucker keeps original vertices
    while (to + 1 < stairs.size() && (stairs[to] - corners[c]).norm() > 1e-12) ++to;
    legs.push_back(fit_line({stairs.begin() + long(from), stairs.begin() + long(to) + 1}).first);
    from = to;
  }
  auto foot = [](const CutLine& l, const Vec2& p) { return Vec2(l.point + l.dir * l.dir.dot(p - l.point)); };
  std::vector<Vec2> out{foot(legs.front(), stairs.front())};
  for (size_t k = 1; k < legs.size(); ++k) {
    auto x = intersect_lines(legs[k - 1].point, legs[k - 1].dir, legs[k].point, legs[k].dir);
    if (x && (*x - corners[k]).norm() < 2 * tolerance) out.push_back(*x);
    else out.push_back(corners[k]);  // legs nearly parallel: keep the corner
  }
  out.push_back(foot(legs.back(), stairs.back()));
  return out;
}

// The shared boundary's pieces sampled by length (see points_along).
std::vector<Vec2> boundary_samples(const std::vector<std::vector<Vec2>>& pieces, double step) {
  std::vector<Vec2> out;
  for (const auto& piece : pieces) {
    const std::vector<Vec2> samples = points_along(piece, step);
    out.insert(out.end(), samples.begin(), samples.end());
  }
  return out;
}

Vec2 local_side_point(const RoofPartitionInput& in, int slot, const MultiPolygon2& corridor,
                      const Vec2& fallback) {
  Vec2 sum = Vec2::Zero();
  int n = 0;
  for (size_t i = 0; i < in.points.size(); ++i)
    if (in.labels[i] == in.components[slot] && poly::covers(corridor, in.points[i]))
      sum += in.points[i], ++n;
  return n > 0 ? Vec2(sum / n) : fallback;
}

// Pieces of a boundary as chains: a piece whose end lies within `gap` of a
// chain's end carries that chain on (shared boundaries come back broken where
// the regions do not quite touch).
std::vector<std::vector<Vec2>> chain_pieces(std::vector<std::vector<Vec2>> pieces, double gap) {
  std::vector<std::vector<Vec2>> chains;
  while (!pieces.empty()) {
    std::vector<Vec2> chain = std::move(pieces.back());
    pieces.pop_back();
    for (bool grown = true; grown;) {
      grown = false;
      for (size_t k = 0; k < pieces.size() && !grown; ++k) {
        auto& p = pieces[k];
        if ((p.front() - chain.back()).norm() < gap) chain.insert(chain.end(), p.begin(), p.end());
        else if ((p.back() - chain.back()).norm() < gap) chain.insert(chain.end(), p.rbegin(), p.rend());
        else if ((p.back() - chain.front()).norm() < gap) chain.insert(chain.begin(), p.begin(), p.end());
        else if ((p.front() - chain.front()).norm() < gap) chain.insert(chain.begin(), p.rbegin(), p.rend());
        else continue;
        pieces.erase(pieces.begin() + long(k));
        grown = true;
      }
    }
    chains.push_back(std::move(chain));
  }
  return chains;
}

// Within `corridor`, region i takes what lies in `side_of_i` and region j the
// rest, tile by tile over the tiles the corridor touches.
void share_corridor(TiledRegions& regions, int i, int j, const MultiPolygon2& corridor,
                    const MultiPolygon2& side_of_i) {
  regions.edit_pair(size_t(i), size_t(j), box_of(corridor), [&](MultiPolygon2& pi, MultiPolygon2& pj) {
    const MultiPolygon2 both = poly::intersect(poly::unite(pi, pj), corridor);
    pi = poly::unite(poly::subtract(pi, corridor), poly::intersect(both, side_of_i));
    pj = poly::unite(poly::subtract(pj, corridor), poly::subtract(both, side_of_i));
  });
}

// A boundary no single line fits (an L-shaped step between roof levels): the
// label grid's staircase along it is replaced by straight legs, each region
// taking its side of them within a corridor.
// Left as a staircase, a step at 45 degrees to the grid is 41 % longer, and so
// is the step wall built on it.
void polyline_cut(const RoofPartitionInput& in, TiledRegions& regions, int i, int j,
                  const std::vector<std::vector<Vec2>>& shared) {
  const double tolerance = kStaircaseCells * in.cell;
  for (const auto& piece : chain_pieces(shared, tolerance)) {
    if (piece.size() < 2 || polyline_length({piece}) < kMinSharedLength) continue;
    if ((piece.front() - piece.back()).norm() < tolerance) continue;  // a ring round an island level
    std::vector<Vec2> line = straight_legs(piece, tolerance);
    const Vec2 out0 = line[0] - line[1], out1 = line.back() - line[line.size() - 2];
    if (out0.norm() < 1e-6 || out1.norm() < 1e-6) continue;
    line.front() += kCutOverrun * out0.normalized();
    line.back() += kCutOverrun * out1.normalized();
    const MultiPolygon2 left = poly::side_strip(line, kCorridor), right = poly::side_strip(line, -kCorridor);
    long on_left = 0, on_right = 0;  // region i's points on either side
    for (size_t k = 0; k < in.points.size(); ++k)
      if (in.labels[k] == in.components[size_t(i)]) {
        if (poly::covers(left, in.points[k])) ++on_left;
        else if (poly::covers(right, in.points[k])) ++on_right;
      }
    if (on_left == on_right) continue;
    share_corridor(regions, i, j, poly::unite(left, right), on_left > on_right ? left : right);
  }
}

void cut_pair(const RoofPartitionInput& in, TiledRegions& regions, int i, int j) {
  // Their shared boundary lies within both boxes: the regions there suffice.
  const Box both = regions.box(size_t(i)).meet(regions.box(size_t(j))).grown(kBoxMargin);
  if (both.empty()) return;
  auto shared = poly::shared_boundary(regions.within(size_t(i), both), regions.within(size_t(j), both), kSharedTol);
  if (polyline_length(shared) < kMinSharedLength) return;
  const auto samples = boundary_samples(shared, kSampleCells * in.cell);
  auto cut = intersection_cut(in.planes[i], in.planes[j], samples);
  if (!cut) cut = step_cut(samples);
  if (!cut) return polyline_cut(in, regions, i, j, shared);
  MultiPolygon2 corridor;
  for (const auto& l : shared) corridor = poly::unite(corridor, poly::buffer_line(l, kCorridor));
  // Only along the shared stretch: carried past its end (where a third plane
  // takes over, as at a valley reaching a ridge) the line would hand that
  // plane's area to one of these two.
  const Vec2 dir = cut->dir.normalized(), across(-dir.y(), dir.x());
  double t0 = 1e18, t1 = -1e18;
  for (const auto& v : samples) {
    const double t = dir.dot(v - cut->point);
    t0 = std::min(t0, t), t1 = std::max(t1, t);
  }
  const Vec2 start = cut->point + (t0 - kCutOverrun) * dir, end = cut->point + (t1 + kCutOverrun) * dir;
  corridor = poly::intersect(corridor, poly::intersect(poly::halfplane_box(start, across, end, kFarBox),
                                                       poly::halfplane_box(end, across, start, kFarBox)));
  Vec2 side = local_side_point(in, i, corridor, samples.front());
  if (std::abs(across.dot(side - cut->point)) < 1e-6) return;
  share_corridor(regions, i, j, corridor, poly::halfplane_box(cut->point, cut->dir, side, kFarBox));
}

// The neighbour a fragment of region `self` joins: the one holding most of
// its points, on equal votes the longer shared boundary; -1 where it has no
// neighbour or its own points hold it.
int fragment_owner(const Polygon2& part, size_t self, const std::vector<MultiPolygon2>& regions,
                   const std::vector<Vec2>& points, const std::vector<int>& region_of_point, ZoneCache& zones) {
  std::vector<int> votes(regions.size(), 0);  // the fragment's points, by their region
  const MultiPolygon2 piece{part};
  const Box pb = box_of(piece);  // a point outside the box is not covered
  for (size_t k = 0; k < points.size(); ++k)
    if (region_of_point[k] >= 0 && pb.near(Box{points[k], points[k]}, 0) && poly::covers(piece, points[k]))
      ++votes[size_t(region_of_point[k])];
  int best = -1;
  double best_len = 0;
  for (size_t j = 0; j < regions.size(); ++j) {
    if (j == self) continue;
    if (!pb.near(zones.box(j), kBoxMargin)) continue;  // further apart than kSharedTol: no boundary shared
    double len = zones.shared_length(piece, j);
    if (len <= 0) continue;  // not a neighbour
    if (best < 0 || votes[j] > votes[size_t(best)] || (votes[j] == votes[size_t(best)] && len > best_len + kLengthTie))
      best_len = len, best = int(j);
  }
  if (best < 0 || votes[self] > votes[size_t(best)]) return -1;
  return best;
}

}  // namespace

size_t add_points_by_height(RoofPartitionInput& in, const std::vector<Vec3>& points, double near, double gap) {
  const MultiPolygon2 outline{in.outline};
  size_t added = 0;
  for (const Vec3& q : points) {
    if (!poly::covers(outline, q.head<2>())) continue;
    size_t best = in.planes.size();
    double best_d = INFINITY, second_d = INFINITY;
    for (size_t k = 0; k < in.planes.size(); ++k) {
      const double d = std::abs(q.z() - in.planes[k].z_at(q.x(), q.y()));
      if (d < best_d) second_d = best_d, best_d = d, best = k;
      else second_d = std::min(second_d, d);
    }
    if (best_d >= near || second_d - best_d <= gap) continue;
    in.points.push_back(q.head<2>());
    in.labels.push_back(in.components[best]);
    ++added;
  }
  return added;
}

std::vector<RoofRegion> partition_roof(const RoofPartitionInput& in) {
  size_t k = in.components.size();
  std::vector<MultiPolygon2> regions;
  if (k == 1) {
    regions = {{in.outline}};
  } else {
    regions = label_regions(in);
    fix_coverage(in.outline, regions, kMinCoverPart);
    // Longest shared boundaries first: they are the most reliable lines.
    std::vector<std::tuple<double, int, int>> pairs;
    ZoneCache zones(regions);
    for (size_t i = 0; i < k; ++i)
      for (size_t j = i + 1; j < k; ++j) {
        if (!zones.box(i).near(zones.box(j), kBoxMargin)) continue;
        double len = zones.shared_length(regions[i], j);
        if (len > kMinSharedLength) pairs.emplace_back(len, int(i), int(j));
      }
    std::sort(pairs.rbegin(), pairs.rend());
    TiledRegions tiled(regions, kTileCells * in.cell);
    for (auto& [len, i, j] : pairs) cut_pair(in, tiled, i, j);
    for (size_t r = 0; r < k; ++r) regions[r] = tiled.whole(r);
    fix_coverage(in.outline, regions, kMinCoverPart);
    std::vector<int> region_of_point(in.labels.size(), -1);
    for (size_t p = 0; p < in.labels.size(); ++p)
      for (size_t r = 0; r < k; ++r)
        if (in.components[r] == in.labels[p]) region_of_point[p] = int(r);
    absorb_fragments(regions, in.points, region_of_point);
    for (auto& r : regions) r = poly::simplify(r, kSimplifyTol);
    fix_coverage(in.outline, regions, kMinCoverPartFine);
    const std::vector<MultiPolygon2> unsnapped = regions;
    roof::snap_to_intersections(in.outline, regions, in.planes);
    roof::undo_folding_snaps(regions, unsnapped);
    roof::remove_overlaps(regions);
    fix_coverage(in.outline, regions, kMinCoverPartFine);
    absorb_fragments(regions, in.points, region_of_point);  // snapping can detach more
  }
  std::vector<RoofRegion> out;
  for (size_t i = 0; i < k; ++i) {
    if (regions[i].empty()) continue;
    out.push_back(RoofRegion{in.components[i], in.planes[i], regions[i]});
  }
  return out;
}

void absorb_fragments(std::vector<MultiPolygon2>& regions, const std::vector<Vec2>& points,
                      const std::vector<int>& region_of_point) {
  // Measured against the regions as they stand, the fragments united at the
  // end: one overlay per region that takes any, and no order between them.
  ZoneCache zones(regions);
  std::vector<MultiPolygon2> keep(regions.size()), gifts(regions.size());
  for (size_t i = 0; i < regions.size(); ++i) {
    if (regions[i].size() < 2) {
      keep[i] = regions[i];
      continue;
    }
    double biggest = 0;
    for (const auto& part : regions[i]) biggest = std::max(biggest, area(part));
    for (const auto& part : regions[i]) {
      const double a = area(part);
      const int to = a >= kFragment || a >= biggest ? -1 : fragment_owner(part, i, regions, points, region_of_point, zones);
      (to < 0 ? keep[i] : gifts[size_t(to)]).push_back(part);
    }
  }
  for (size_t i = 0; i < regions.size(); ++i)
    regions[i] = gifts[i].empty() ? keep[i] : poly::unite_all({keep[i], gifts[i]});
}

}  // namespace c3d
