#pragma once
// The Slurm runner of a sharded batch (docs/scale.md, "Sharding and Slurm"):
// a job array of N tasks, task K running `cadastre3d batch ... --shard K/N
// --resume`, and a finish job after it: `merge` of the shards' GeoPackages,
// or `merge --store` of one shared store, with the batch's inputs for the
// whole-run fit. Slurm schedules, reruns and
// accounts; this file writes the scripts and calls sbatch.
#include <string>
#include <vector>

namespace c3d {

struct SlurmPlan {
  std::string exe;                      // the cadastre3d the tasks run (absolute)
  std::string workdir;                  // where tasks start: relative input paths hold there
  std::string out;                      // OUT (absolute): OUT/slurm, OUT/shards/K, the merged outputs
  int shards = 1;                       // N
  std::vector<std::string> batch_args;  // the batch's input options, as given
  std::string store;                    // --store LOC shared by all shards; "": a GeoPackage per shard + merge
  std::string formats;                  // the finish step's exports (comma list); "": the batch's default
  std::vector<std::string> input_args;  // the batch's input options (--cloud=..., ...): the finish step's fit
  int cpus_per_task = 0;                // 0: Slurm's default; each task runs --jobs of its CPUs
  std::vector<std::string> sbatch_options;  // more #SBATCH lines, e.g. --partition=cpu
  std::string launcher;  // shell words every cadastre3d of the scripts runs under (srun, /usr/bin/time ...); "": none
};

struct SlurmScripts {
  std::string shards, finish, rerun;  // OUT/slurm/{shards,finish}.sbatch, OUT/slurm/rerun.sh
};

// Writes the three scripts (executable) and returns their paths.
SlurmScripts write_slurm_scripts(const SlurmPlan& plan);

struct SlurmJobs {
  std::string shards, finish;  // job ids
};

// Submits the array, then the finish job with --dependency=afterok on it;
// records the ids in OUT/slurm/*.jobid for rerun.sh. InputError when sbatch fails.
SlurmJobs submit_slurm(const SlurmScripts& scripts);

// 'text' quoted for a POSIX shell.
std::string shell_quote(const std::string& text);

}  // namespace c3d
