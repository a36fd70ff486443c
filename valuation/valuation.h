#pragma once
// Cost-approach valuation of one parcel (PBB-P2 practice):
//   building = sum(element area x unit cost x quality factor) x (1 - depreciation)
//   land     = parcel area (official if known, else computed) x zone land price
//   NJOP     = land + building;  tax = rate x max(0, NJOP - NJOPTKP)
// Uncertainties: sigma_amount = unit cost x sigma_area, sums in quadrature.
#include <vector>

#include "core/config/config.h"
#include "core/types.h"
#include "valuation/valuation_types.h"

namespace c3d {

// Land area used for valuation: official area when known (> 0), else computed.
double valuation_land_area(const Parcel& parcel, std::string* source = nullptr);

// Values one parcel. Zone, quality and age come from params.parcels[parcel.id]
// when set, else from the defaults. Failed parcels get land value only (note says why).
ParcelValuation value_parcel(const Parcel& parcel, const ParcelResult& result,
                             const ValuationParams& params);

// Values every parcel of a batch (same order as model.parcels).
std::vector<ParcelValuation> value_batch(const BatchModel& model, const ValuationParams& params);

}  // namespace c3d
