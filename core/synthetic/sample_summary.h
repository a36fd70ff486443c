#pragma once
// A sample town seen as the batch's output would be (its truth as a model) and
// counted for the summary `cadastre3d sample` prints.
#include <map>
#include <string>

#include "core/synthetic/sample_town.h"
#include "core/types.h"

namespace c3d {

// The exact buildings as the batch would hold them, one result per parcel
// (Empty where the parcel has no building), so that they can be written as the
// batch writes its models and measured with the batch's ruler: the figures a
// flawless reconstruction of the town's points gets.
BatchModel truth_model(const SampleTown& town);

struct SampleTownCounts {
  std::map<std::string, int> layouts;  // parcels per layout name
  int buildings = 0;
  long roof_points = 0, wall_points = 0, other_points = 0;  // classes 6, 64, the rest (ground)
};
SampleTownCounts count_town(const SampleTown& town);

// The lines `sample` prints about the town and the files written (its truth
// models in truth_obj_dir), before the timing line.
std::string sample_town_text(const SampleTown& town, const SampleFiles& files, const std::string& truth_obj_dir);

}  // namespace c3d
