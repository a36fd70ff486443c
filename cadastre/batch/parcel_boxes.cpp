#include "cadastre/batch/parcel_boxes.h"

namespace c3d {
namespace {

// A few parcels across: a chunk's query visits few cells, a parcel lies in few.
constexpr double kCellM = 64;

std::vector<Box> boxes_of(const ParcelLayer& layer) {
  std::vector<Box> boxes;
  boxes.reserve(layer.parcels.size());
  for (const Parcel& p : layer.parcels) boxes.push_back(box_of(p.shape));
  return boxes;
}

}  // namespace

ParcelBoxes::ParcelBoxes(const ParcelLayer& layer) : BoxGrid(boxes_of(layer), kCellM) {}

}  // namespace c3d
