// cadastre3d slurm --shards N --out OUT [--store LOC] [--submit] BATCH_OPTIONS...
// Writes OUT/slurm/shards.sbatch (a job array: task K runs `batch ... --shard
// K/N --resume`), OUT/slurm/finish.sbatch (merge, or report + export from a
// shared --store) and OUT/slurm/rerun.sh; --submit submits them
// (cadastre/batch/slurm.h). The batch's options are the batch's own: checked
// by its parser, passed on as given.
#include <filesystem>
#include <iostream>
#include <memory>

#include "cadastre/batch/slurm.h"
#include "cli/commands.h"
#include "core/error.h"

namespace fs = std::filesystem;

namespace c3d::cli {
namespace {

struct SlurmArgs {
  int shards = 0;
  std::string out, store;
  bool submit = false, dry_run = false;
  int cpus_per_task = 0;
  std::vector<std::string> sbatch_options;
};

// Options the runner sets on every task itself.
const char* const kRunnerOwned[] = {"--out", "--shard", "--resume", "--overwrite", "--store"};

// Parses the batch options with `batch`'s own parser (without running it), so
// a wrong option fails here, not in N tasks; returns its --formats (comma list).
std::string check_batch_options(const std::vector<std::string>& args, const std::string& out) {
  for (const auto& a : args)
    for (const char* owned : kRunnerOwned)
      if (a == owned || a.rfind(std::string(owned) + "=", 0) == 0)
        throw InputError(a, "is set by the Slurm runner for each task; leave it out");
  CLI::App app;
  register_batch(app, true);
  CLI::App* batch = app.get_subcommand("batch");
  std::vector<std::string> argv = {"batch"};
  argv.insert(argv.end(), args.begin(), args.end());
  argv.insert(argv.end(), {"--out", out});
  std::vector<std::string> reversed(argv.rbegin(), argv.rend());  // CLI11 takes them last first
  app.parse(reversed);
  std::string formats;
  for (const auto& f : batch->get_option("--formats")->results()) formats += (formats.empty() ? "" : ",") + f;
  return formats;
}

void run(const SlurmArgs& a, const std::vector<std::string>& batch_args) {
  SlurmPlan plan;
  plan.out = fs::absolute(a.out).lexically_normal().string();
  plan.formats = check_batch_options(batch_args, plan.out + "/shards/1");
  std::error_code ec;
  plan.exe = fs::read_symlink("/proc/self/exe", ec).string();
  if (ec) plan.exe = "cadastre3d";
  plan.workdir = fs::current_path().string();
  plan.shards = a.shards;
  plan.batch_args = batch_args;
  plan.store = a.store;
  plan.cpus_per_task = a.cpus_per_task;
  plan.sbatch_options = a.sbatch_options;
  const SlurmScripts s = write_slurm_scripts(plan);
  std::cout << "array:  " << s.shards << "\nfinish: " << s.finish << "\nrerun:  " << s.rerun << " K  (a killed task)\n";
  if (!a.submit) {
    std::cout << "submit: job=$(sbatch --parsable " << s.shards << ") && sbatch --dependency=afterok:$job " << s.finish
              << "\n";
    return;
  }
  const SlurmJobs j = submit_slurm(s);
  std::cout << "shards: job " << j.shards << " (array 1-" << a.shards << ")\nfinish: job " << j.finish
            << " (after every shard)\n";
}

}  // namespace

void register_slurm(CLI::App& app) {
  auto a = std::make_shared<SlurmArgs>();
  auto* cmd = app.add_subcommand(
      "slurm",
      "Run a batch as N shards on Slurm: writes OUT/slurm/shards.sbatch (a job array of `batch --shard K/N "
      "--resume`) and finish.sbatch (merge, or report + export from --store); the batch's options follow");
  cmd->allow_extras();
  cmd->add_option("--shards", a->shards, "Number of shards N (array tasks)")->required()->check(CLI::Range(1, 100000));
  cmd->add_option("--out", a->out, "Output directory: OUT/slurm, OUT/shards/K, the merged outputs")->required();
  cmd->add_option("--store", a->store, "One store all shards write (postgresql://...): no merge");
  cmd->add_option("--cpus-per-task", a->cpus_per_task, "CPUs per task (#SBATCH); the batch runs as many --jobs")
      ->check(CLI::Range(1, 4096));
  cmd->add_option("--sbatch", a->sbatch_options, "One more #SBATCH line for both scripts, e.g. --sbatch=--partition=cpu");
  auto* submit = cmd->add_flag("--submit", a->submit, "Submit the array and the finish job (sbatch); prints their job ids");
  cmd->add_flag("--dry-run", a->dry_run, "Write the scripts only and print how to submit them (the default)")
      ->excludes(submit);
  cmd->callback([a, cmd] {
    run(*a, cmd->remaining());
    exit_code() = kExitOk;
  });
}

}  // namespace c3d::cli
