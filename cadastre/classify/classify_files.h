#pragma once
// `cadastre3d classify` on files: a point file into a classified LAS, or a
// folder of tiles into a folder, one tile in memory at a time.
#include <ostream>
#include <string>

#include "core/classify/forest.h"
#include "core/types.h"

namespace c3d {

// Classifies `in` (a point file, or a folder of them) into `out` (a LAS file,
// or a folder of <name>.las), over the DTM file `dtm` or, empty, the terrain
// found in each cloud; writes what it did to log, a file at a time. Each tile
// of a folder is classified on its own points.
void classify_files(const PointForest& forest, const ClassMapping& classes, const std::string& in,
                    const std::string& out, const std::string& dtm, std::ostream& log);

}  // namespace c3d
