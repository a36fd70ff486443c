#pragma once
// Small valid inputs for every reader, generated in code (no files in the
// repository; LAZ from ../shared): the fuzzer's starting points.
#include <string>
#include <vector>

#include "tests/fuzz/fuzz_mutate.h"

namespace c3d::fuzz {

// Seeds per reader; work is a scratch directory for the writers that need a file.
std::vector<SeedInput> las_seeds(const std::string& work);
// LAZ seeds are files of ../shared/data/laz (no LAZ encoder here): none when absent.
std::vector<SeedInput> laz_seeds();
std::vector<SeedInput> ply_seeds();
std::vector<SeedInput> pcd_seeds(const std::string& work);
std::vector<SeedInput> xyz_seeds();
std::vector<SeedInput> dtm_seeds();
std::vector<SeedInput> parcel_seeds(const std::string& work);
std::vector<SeedInput> config_seeds();
std::vector<SeedInput> mesh_seeds();

}  // namespace c3d::fuzz
