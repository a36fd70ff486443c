#pragma once
// The whole-run fit of the models (BatchReport: any_model_*, the rulers, the
// share of wall points measured) of a store that shards wrote: the merged
// store of `merge`, or one PostgreSQL store every shard wrote. A shard cannot
// compute it (its neighbours' models are in other shards) and a store holds
// no points; from the batch's inputs and the whole store it is the unsharded
// run's (any_model_deviation reads the models back from the store).
#include <string>

#include "cadastre/batch/batch.h"
#include "cadastre/batch/batch_inputs.h"

namespace c3d {

// The batch's inputs and configuration, as the shards ran with them.
struct RunInputs {
  BatchInputs inputs;
  Config cfg;
};

// The fit's inputs (load_fit_inputs), refused (InputError, one line naming
// what differs) unless they are the run's of `stores` (a run's shards'
// stores, or one store they all wrote): its parameters, its input files
// (SHA-256), the parcels the layer selects (--layer, --where, --bbox: each
// stored parcel one they select, all of them once every shard is in).
// Reads the layer, the tiles' headers and every input file once (SHA-256);
// no cell of the DTM, no survey pass, no model.
LoadedInputs load_run_inputs(const RunInputs& run, const std::vector<std::string>& stores);

// The whole-run fit of the models in `store` (any_model_deviation, reading
// them back from it a page at a time) into report: every point near the
// parcels read once more from the tiles.
void store_fit(const LoadedInputs& in, const Config& cfg, const std::string& store, BatchReport& report);

// What differs first between two run parameters (JSON text), the config
// file's name and [batch] aside ("key: A here, B there"); "" when they are
// the same run's.
std::string parameters_difference(const std::string& a, const std::string& b);

}  // namespace c3d
