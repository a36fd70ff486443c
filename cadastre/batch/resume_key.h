#pragma once
// What a stored parcel result depends on, as one key: --resume keeps a
// parcel only when its key is unchanged.
#include <string>
#include <vector>

#include "core/config/config.h"
#include "core/io/sha256.h"
#include "core/types.h"

namespace c3d {

// The effective configuration as the run record stores it (JSON text): every
// parameter after the command line's overrides, and the file it came from.
std::string run_parameters(const Config& cfg);

// The key of a whole run: config_fingerprint (every parameter, not the file's
// name) and the SHA-256 of every input file's content (not its name).
std::string run_key(const Config& cfg, const std::vector<InputFile>& inputs);

// A parcel's key: the run key, its id and its own shape, and the SHA-256 of
// each point file it can read (cadastre/batch/batch_inputs.h, parcel_keys).
std::string parcel_key(const std::string& run_key, const Parcel& p, const std::vector<std::string>& tiles = {});

}  // namespace c3d
