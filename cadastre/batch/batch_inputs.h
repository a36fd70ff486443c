#pragma once
// The batch's first step: the parcel layer and the DTM read, the clouds'
// files indexed as tiles (cadastre/batch/tiles.h) and surveyed once, all in
// one CRS, and the batch's local frame. The points themselves are read a
// region at a time (read_region), never all at once.
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "cadastre/batch/batch.h"
#include "cadastre/batch/parcel_boxes.h"
#include "cadastre/batch/plausibility.h"
#include "cadastre/batch/shard.h"
#include "cadastre/batch/tiles.h"
#include "cadastre/parcels.h"
#include "core/io/dtm_io.h"
#include "core/io/sha256.h"

namespace c3d {

struct LoadedInputs {
  ParcelLayer layer;
  ParcelBoxes boxes;  // the layer's parcel boxes (working CRS), with their grid
  Dtm dtm;  // with --dtm its header only (extent, CRS): cells come from dtm_source
  std::shared_ptr<const DtmSource> dtm_source;  // --dtm, read a window at a time
  std::vector<Tile> tiles;       // the --cloud files, then the --walls files
  std::vector<std::string> cloud_files, wall_files;  // the files --cloud and --walls name
  PointCoverage coverage;        // where the clouds have points of any class
  std::string crs_wkt;
  std::vector<std::string> warnings;
  std::map<std::string, InputFile> described;  // tiles hashed while indexed, by path: hashed once
};

// The inputs for modelling the parcels `work` picks of the layer (a shard's,
// or all): only the tiles within reach of them are kept and surveyed (with
// --dtm; a DTM built from ground points takes every tile). Throws InputError
// naming the file when an input is unusable.
LoadedInputs load_inputs(const BatchInputs& inputs, const Config& cfg, const Shard& work = {});

// What the whole-run fit (any_model_deviation) reads, and no more: the layer
// and the tiles' index (file headers) in the batch's working CRS (the DTM's
// header only). No cell of the DTM, no survey pass, no model; with --classify
// the clouds are classified again as the batch did. coverage and dtm cells
// stay empty.
LoadedInputs load_fit_inputs(const BatchInputs& inputs, const Config& cfg);

// Every input file the run reads (folders and globs expanded) with its
// SHA-256 (each file read once) and its role (input_role): clouds, walls,
// the parcel layer, the DTM, the classifier. The run record.
std::vector<InputFile> describe_inputs(const LoadedInputs& in, const BatchInputs& inputs);

// Per parcel of the layer, its resume key (resume_key.h): the parameters,
// the layer and DTM files, and the point files it can read: with --dtm the
// tiles touching the roof-density blocks within its reach, so a shard's key
// is the unsharded run's and a file added far away changes no key; without,
// every tile (the ground DTM is built from all).
std::vector<std::string> parcel_keys(const LoadedInputs& in, const BatchInputs& inputs, const Config& cfg,
                                     const std::vector<InputFile>& files);

// Why parcel i cannot be modelled from these inputs (no point of the clouds
// near it, no DTM under it), or "".
std::string unreachable(const LoadedInputs& in, size_t i);

// The --dtm cells under the box (DtmSource::window); without --dtm an empty Dtm
// (in.dtm, built from ground points, is held whole).
Dtm dtm_window(const LoadedInputs& in, const Box& box);

// The batch's local origin: the south-west corner of the layer, on a 10 m grid.
LocalFrame frame_of(const ParcelLayer& layer);

}  // namespace c3d
