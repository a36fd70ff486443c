#pragma once
// The batch-wide fit of the models (BatchReport: any_model_roof and
// any_model_wall, the roof and wall rulers, the share of wall points
// measured), a chunk of parcels at a time: the chunk's points read again from
// the tiles, the models of its parcels and of the parcels around it read from
// the sink, each point counted once, its distance to the nearest face of any
// model. Memory is bounded by a chunk's points and the models near it.
#include "cadastre/batch/batch.h"
#include "cadastre/batch/batch_inputs.h"

namespace c3d {

void any_model_deviation(const LoadedInputs& in, const Config& cfg, BatchSink& sink, BatchReport& report);

}  // namespace c3d
