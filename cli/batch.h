#pragma once
// The main job: parcel batch from point clouds, parcels and a DTM to the store,
// summary.json, report and exports. The stages are in the libraries; this file
// only wires them and keeps one bad parcel from stopping the others.
#include <string>
#include <vector>

namespace c3d::cli {

struct BatchOptions {
  std::vector<std::string> clouds;   // classified clouds (roof / wall / ground classes)
  std::vector<std::string> walls;    // clouds of wall points only (terrestrial scanner)
  std::string parcels;
  std::string dtm;                   // empty: built from ground-class points
  std::string out;
  std::string config;                // empty: built-in defaults
  std::vector<std::string> formats{"gml", "cityjson", "ifc", "obj"};
  int jobs = 0;                      // 0: all cores
  bool resume = false;
  bool optimize = false;
  std::string device;                // optimizer device: auto | cpu | vulkan
  bool quiet = false;
};

// Returns the process exit code (commands.h).
int run_batch(const BatchOptions& opt);

}  // namespace c3d::cli
