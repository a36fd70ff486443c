#include "core/classify/ground_filter.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>

#include <pcl/point_types.h>
#include <pcl/segmentation/approximate_progressive_morphological_filter.h>

namespace c3d {
namespace {

constexpr double kEmpty = std::numeric_limits<double>::quiet_NaN();

// A raster of nx x ny cells, row-major, NaN where empty.
struct Grid {
  int nx = 0, ny = 0;
  std::vector<double> z;
  double& at(int i, int j) { return z[size_t(j) * size_t(nx) + size_t(i)]; }
  double at(int i, int j) const { return z[size_t(j) * size_t(nx) + size_t(i)]; }
};

// Empty cells take the mean of their filled neighbours, ring by ring outward
// from the filled ones (breadth first): a smooth enough fill for the small
// gaps under roofs and trees, linear in the cells.
void fill_empty(Grid& g) {
  std::deque<std::pair<int, int>> queue;
  std::vector<char> done(g.z.size(), 0);
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i)
      if (std::isfinite(g.at(i, j))) done[size_t(j) * size_t(g.nx) + size_t(i)] = 1, queue.emplace_back(i, j);
  if (queue.empty()) return;
  std::vector<char> queued = done;
  for (size_t k = 0; k < queue.size(); ++k) {
    const auto [i, j] = queue[k];
    for (int b = std::max(0, j - 1); b <= std::min(g.ny - 1, j + 1); ++b)
      for (int a = std::max(0, i - 1); a <= std::min(g.nx - 1, i + 1); ++a) {
        const size_t c = size_t(b) * size_t(g.nx) + size_t(a);
        if (queued[c]) continue;
        queued[c] = 1;
        queue.emplace_back(a, b);
      }
    if (done[size_t(j) * size_t(g.nx) + size_t(i)]) continue;
    double sum = 0;
    int n = 0;
    for (int b = std::max(0, j - 1); b <= std::min(g.ny - 1, j + 1); ++b)
      for (int a = std::max(0, i - 1); a <= std::min(g.nx - 1, i + 1); ++a)
        if (done[size_t(b) * size_t(g.nx) + size_t(a)]) sum += g.at(a, b), ++n;
    g.at(i, j) = sum / n;  // a cell is queued next to a done one, so n > 0
    done[size_t(j) * size_t(g.nx) + size_t(i)] = 1;
  }
}

// Sliding minimum (or maximum) over 2r + 1 values of a line, in place
// (a monotone deque: linear in the line whatever r).
template <typename Better>
void slide(std::vector<double>& line, int r, Better better) {
  const int n = int(line.size());
  std::vector<double> out(line.size());
  std::deque<int> best;
  for (int k = 0; k < n + r; ++k) {
    if (k < n) {
      while (!best.empty() && !better(line[size_t(best.back())], line[size_t(k)])) best.pop_back();
      best.push_back(k);
    }
    const int centre = k - r;
    if (centre < 0) continue;
    while (best.front() < centre - r) best.pop_front();
    out[size_t(centre)] = line[size_t(best.front())];
  }
  line = std::move(out);
}

// Erosion or dilation by a square window of 2r + 1 cells: rows, then columns.
template <typename Better>
Grid filtered(const Grid& g, int r, Better better) {
  Grid out = g;
  std::vector<double> line;
  for (int j = 0; j < g.ny; ++j) {
    line.assign(out.z.begin() + long(j) * g.nx, out.z.begin() + long(j + 1) * g.nx);
    slide(line, r, better);
    std::copy(line.begin(), line.end(), out.z.begin() + long(j) * g.nx);
  }
  for (int i = 0; i < g.nx; ++i) {
    line.resize(size_t(g.ny));
    for (int j = 0; j < g.ny; ++j) line[size_t(j)] = out.at(i, j);
    slide(line, r, better);
    for (int j = 0; j < g.ny; ++j) out.at(i, j) = line[size_t(j)];
  }
  return out;
}

Grid opened(const Grid& g, int r) {
  return filtered(filtered(g, r, std::less_equal<double>()), r, std::greater_equal<double>());
}

// The terrain's slope (rise over run) at each cell, by central differences.
double slope_at(const Grid& g, int i, int j, double cell) {
  const int i0 = std::max(0, i - 1), i1 = std::min(g.nx - 1, i + 1);
  const int j0 = std::max(0, j - 1), j1 = std::min(g.ny - 1, j + 1);
  const double gx = i1 > i0 ? (g.at(i1, j) - g.at(i0, j)) / ((i1 - i0) * cell) : 0;
  const double gy = j1 > j0 ? (g.at(i, j1) - g.at(i, j0)) / ((j1 - j0) * cell) : 0;
  return std::hypot(gx, gy);
}

}  // namespace

GroundFilter smrf_ground(const std::vector<Vec3>& world, const SmrfParams& p) {
  GroundFilter out;
  out.ground.assign(world.size(), 0);
  if (world.empty()) return out;
  Vec3 lo = world.front(), hi = world.front();
  for (const Vec3& q : world) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
  Grid surface;
  surface.nx = int(std::floor((hi.x() - lo.x()) / p.cell)) + 1;
  surface.ny = int(std::floor((hi.y() - lo.y()) / p.cell)) + 1;
  surface.z.assign(size_t(surface.nx) * size_t(surface.ny), kEmpty);
  const auto cell_of = [&](const Vec3& q) {
    return std::pair{std::min(surface.nx - 1, int((q.x() - lo.x()) / p.cell)),
                     std::min(surface.ny - 1, int((q.y() - lo.y()) / p.cell))};
  };
  for (const Vec3& q : world) {  // heights above the lowest point: doubles near zero
    const auto [i, j] = cell_of(q);
    double& z = surface.at(i, j);
    if (!(z <= q.z() - lo.z())) z = q.z() - lo.z();
  }
  const Grid lowest = surface;
  fill_empty(surface);
  // Progressive opening: a window one cell wider each step; a cell the
  // opening lowers by more than the slope allows over the window's radius is
  // an object's.
  std::vector<char> object(surface.z.size(), 0);
  const int widest = std::max(1, int(std::lround(p.max_window_m / p.cell / 2)));
  Grid last = surface;
  for (int r = 1; r <= widest; ++r) {
    Grid next = opened(last, r);
    const double allowed = p.slope * r * p.cell;
    for (size_t c = 0; c < next.z.size(); ++c)
      if (last.z[c] - next.z[c] > allowed) object[c] = 1;
    last = std::move(next);
  }
  Grid terrain = lowest;
  for (size_t c = 0; c < terrain.z.size(); ++c)
    if (object[c]) terrain.z[c] = kEmpty, ++out.objects;
  fill_empty(terrain);
  if (!std::isfinite(terrain.z.front())) terrain = surface;  // every cell an object: no better guess
  // Each point against the terrain at its place (bilinear, cell centres).
  Dtm& d = out.terrain;
  d.x0 = lo.x() + p.cell / 2, d.y0 = lo.y() + p.cell / 2, d.dx = d.dy = p.cell;
  d.nx = terrain.nx, d.ny = terrain.ny;
  d.z.resize(terrain.z.size());
  for (size_t c = 0; c < terrain.z.size(); ++c) d.z[c] = float(terrain.z[c] + lo.z());
  for (size_t k = 0; k < world.size(); ++k) {
    const auto [i, j] = cell_of(world[k]);
    const double allowed = p.elevation_m + p.elevation_scalar * slope_at(terrain, i, j, p.cell);
    const double x = std::clamp(world[k].x(), d.x0, d.x0 + (d.nx - 1) * d.dx);
    const double y = std::clamp(world[k].y(), d.y0, d.y0 + (d.ny - 1) * d.dy);
    out.ground[k] = std::abs(world[k].z() - d.height_at(x, y)) <= allowed;
  }
  return out;
}

std::vector<char> pcl_pmf_ground(const std::vector<Vec3>& world, const SmrfParams& p) {
  std::vector<char> out(world.size(), 0);
  if (world.empty()) return out;
  Vec3 lo = world.front();
  for (const Vec3& q : world) lo = lo.cwiseMin(q);
  auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  cloud->reserve(world.size());
  for (const Vec3& q : world) {  // float near zero: the local frame
    const Vec3 l = q - lo;
    cloud->push_back(pcl::PointXYZ(float(l.x()), float(l.y()), float(l.z())));
  }
  pcl::ApproximateProgressiveMorphologicalFilter<pcl::PointXYZ> pmf;
  pmf.setInputCloud(cloud);
  pmf.setCellSize(float(p.cell));
  pmf.setMaxWindowSize(int(std::lround(p.max_window_m / p.cell)));
  pmf.setSlope(float(p.slope));
  pmf.setInitialDistance(float(p.elevation_m));
  pmf.setMaxDistance(3.0f);  // Zhang et al.'s: no step of the terrain higher than 3 m
  std::vector<int> ground;
  pmf.extract(ground);
  for (int i : ground) out[size_t(i)] = 1;
  return out;
}

}  // namespace c3d
