// Classification speed (not a test; scripts/bench_classify.sh): joins the given
// labelled tiles into one survey, lays COPIES x COPIES of it side by side (a
// national tile's size from a town's points), writes it unclassified to OUT.las
// for the whole-process run, and prints each stage's CPU time per point.
// Usage: c3d_bench_classify MODEL OUT.las COPIES TILE...
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <exception>
#include <string>

#include "core/classify/classify.h"
#include "core/io/point_io.h"

namespace {

double cpu_seconds() { return double(std::clock()) / CLOCKS_PER_SEC; }

c3d::PointCloud tiled(const std::vector<std::string>& files, int copies) {
  c3d::PointCloud one;
  for (const auto& f : files) {
    c3d::PointCloud t = c3d::read_point_cloud(f);
    if (one.crs_wkt.empty()) one.crs_wkt = t.crs_wkt;
    one.points.insert(one.points.end(), t.points.begin(), t.points.end());
    t.returns.resize(t.points.size(), c3d::pack_returns(1, 1));
    one.returns.insert(one.returns.end(), t.returns.begin(), t.returns.end());
  }
  c3d::Vec3 lo = one.points.front(), hi = lo;
  for (const auto& p : one.points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  c3d::PointCloud all;
  all.crs_wkt = one.crs_wkt;
  for (int i = 0; i < copies; ++i)
    for (int j = 0; j < copies; ++j) {
      const c3d::Vec3 shift(i * (hi.x() - lo.x() + 1), j * (hi.y() - lo.y() + 1), 0);
      for (const auto& p : one.points) all.points.push_back(p + shift);
      all.returns.insert(all.returns.end(), one.returns.begin(), one.returns.end());
    }
  return all;
}

void stage(const char* name, double seconds, size_t points) {
  std::printf("  %-14s %7.2f CPU s  %9.0f points per CPU-second\n", name, seconds, points / std::max(seconds, 1e-9));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 5) {
    std::fprintf(stderr, "usage: %s MODEL OUT.las COPIES TILE...\n", argv[0]);
    return 2;
  }
  try {
    const c3d::PointForest forest = c3d::PointForest::load(argv[1]);
    const c3d::PointCloud cloud = tiled(std::vector<std::string>(argv + 4, argv + argc), std::atoi(argv[3]));
    c3d::write_las(argv[2], cloud);
    std::printf("%zu points\n", cloud.points.size());
    double t = cpu_seconds();
    const c3d::Dtm terrain = c3d::terrain_from_cloud(cloud, c3d::ClassMapping{}, nullptr);
    const double ground = cpu_seconds() - t;
    t = cpu_seconds();
    const c3d::FeatureTable features = c3d::cloud_features(cloud, terrain);
    const double feat = cpu_seconds() - t;
    t = cpu_seconds();
    const auto classes = forest.predict(features);
    const double predict = cpu_seconds() - t;
    stage("ground filter", ground, cloud.points.size());
    stage("features", feat, cloud.points.size());
    stage("forest", predict, cloud.points.size());
    stage("together", ground + feat + predict, cloud.points.size());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
