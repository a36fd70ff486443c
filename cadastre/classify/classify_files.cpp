#include "cadastre/classify/classify_files.h"

#include <filesystem>

#include "cadastre/batch/tiles.h"
#include "core/classify/classify.h"
#include "core/io/dtm_io.h"
#include "core/io/point_io.h"

namespace c3d {
namespace {

void classify_file(const PointForest& forest, const ClassMapping& classes, const std::string& in,
                   const std::string& out, const std::string& dtm, std::ostream& log) {
  PointCloud cloud = read_point_cloud(in);
  std::string note = "terrain from " + dtm;
  const Dtm terrain = dtm.empty() ? terrain_from_cloud(cloud, classes, &note) : read_dtm(dtm);
  const Classification c = classify_points(forest, cloud, terrain);
  write_classes(cloud, c.classes, classes);
  write_las(out, cloud);
  log << "classify: " << cloud.points.size() << " points (" << note << ")\n";
  for (int k = 0; k < kPointClassCount; ++k)
    log << "  " << to_string(PointClass(k)) << " (class " << int(class_code(PointClass(k), classes))
        << "): " << c.counts[k] << "\n";
  log << "written: " << out << "\n" << std::flush;
}

}  // namespace

void classify_files(const PointForest& forest, const ClassMapping& classes, const std::string& in,
                    const std::string& out, const std::string& dtm, std::ostream& log) {
  namespace fs = std::filesystem;
  if (!fs::is_directory(in)) return classify_file(forest, classes, in, out, dtm, log);
  fs::create_directories(out);
  for (const auto& tile : expand_point_files({in}))
    classify_file(forest, classes, tile, (fs::path(out) / (fs::path(tile).stem().string() + ".las")).string(), dtm,
                  log);
}

}  // namespace c3d
