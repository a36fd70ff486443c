#pragma once
// How many points each parcel gets from the clouds (inside it, in its overhang
// buffer, of the roof and wall classes): the check before a batch.
#include <string>
#include <vector>

#include "core/types.h"

namespace c3d {

struct ParcelPointCount {
  long in_parcel = 0;  // strictly inside the parcel
  long in_buffer = 0;  // outside it but within the buffer
  long roof = 0, wall = 0;  // of those, in the roof and the wall classes
};

struct ClipCounts {
  std::vector<ParcelPointCount> parcels;  // layer order
  long points = 0;      // in all clouds
  long unclipped = 0;   // in no parcel's buffer
  bool any_classes = false;  // some cloud carries classes (else roof/wall are 0)
  double buffer_m = 0;
};

// Clouds in the layer's CRS (see read_parcels_for_clouds).
ClipCounts count_points_per_parcel(const ParcelLayer& layer, const std::vector<PointCloud>& clouds,
                                   double buffer_m, const ClassMapping& classes = {});

// The table `clip` prints: a row per parcel and the totals.
std::string clip_table(const ParcelLayer& layer, const ClipCounts& counts);

// parcel_index,parcel_id,in_parcel,in_buffer,roof,wall; throws InputError when
// the file cannot be written.
void write_clip_csv(const std::string& path, const ParcelLayer& layer, const ClipCounts& counts);

}  // namespace c3d
