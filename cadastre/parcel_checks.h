#pragma once
// Checks on a whole parcel layer before any work starts (docs/inputs.md).
#include <map>
#include <string>
#include <vector>

#include "core/config/config.h"
#include "core/types.h"

namespace c3d {

struct ParcelOverlap {
  size_t a = 0, b = 0;  // parcel indexes, a < b
  double area = 0;      // m2 (layer units squared)
};

// Pairs of parcels whose areas overlap by more than kMinOverlapM2, in layer order.
std::vector<ParcelOverlap> parcel_overlaps(const ParcelLayer& layer);

// "parcels A and B overlap by 12.30 m2; ..." one warning per pair.
std::vector<std::string> overlap_warnings(const ParcelLayer& layer);

// Throws InputError naming the id when a per-parcel override ([valuation.parcels])
// names no parcel of the layer; `selected` (a --where or --bbox is in force)
// makes it a warning instead, as the parcel may lie outside the selection.
void check_override_ids(const std::map<std::string, ParcelValuationOverride>& overrides, const ParcelLayer& layer,
                        const std::string& config_source, bool selected, std::vector<std::string>& warnings);

}  // namespace c3d
