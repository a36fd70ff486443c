// cadastre3d slurm --shards N --out OUT [--store LOC] [--launcher CMD] [--submit] BATCH_OPTIONS...
// writes and submits the Slurm job array of a sharded batch (cadastre/batch/slurm.h).
// The batch's options are checked by `batch`'s own parser and passed on as given.
#include <filesystem>
#include <iostream>
#include <memory>

#include "cadastre/batch/slurm.h"
#include "cli/commands.h"
#include "core/error.h"

namespace fs = std::filesystem;

namespace c3d::cli {
namespace {

// Parses the batch options without running a batch, so a wrong one fails
// here, not in N tasks; sets the finish step's --formats (a comma list) and
// the batch's input options, as --name=value, for its whole-run fit.
void check_batch_options(const std::vector<std::string>& args, const std::string& out, SlurmPlan& plan) {
  for (const auto& a : args)
    for (const std::string owned : {"--out", "--shard", "--resume", "--overwrite", "--store"})
      if (a == owned || a.rfind(owned + "=", 0) == 0) throw InputError(a, "the Slurm runner sets it for each task");
  CLI::App app;
  register_batch(app, true);
  std::vector<std::string> argv = {"batch"};
  argv.insert(argv.end(), args.begin(), args.end());
  argv.insert(argv.end(), {"--out", out});
  std::vector<std::string> reversed(argv.rbegin(), argv.rend());  // CLI11 takes them last first
  app.parse(reversed);
  const CLI::App* batch = app.get_subcommand("batch");
  for (const auto& f : batch->get_option("--formats")->results())
    plan.formats += (plan.formats.empty() ? "" : ",") + f;
  for (const CLI::Option* o : batch->get_options()) {
    if (o->get_group() != kInputGroup || o->count() == 0) continue;
    std::string joined;  // a flag: its name; --bbox: its four values in one, by its delimiter
    for (const auto& v : o->results())
      if (o->get_type_size() == 0 || o->get_delimiter() == '\0') plan.input_args.push_back(o->get_name() + (o->get_type_size() ? "=" + v : ""));
      else joined += (joined.empty() ? "" : std::string(1, o->get_delimiter())) + v;
    if (!joined.empty()) plan.input_args.push_back(o->get_name() + "=" + joined);
  }
}

}  // namespace

void register_slurm(CLI::App& app) {
  auto plan = std::make_shared<SlurmPlan>();
  auto submit = std::make_shared<bool>(false);
  auto* cmd = app.add_subcommand("slurm",
                                 "Run a batch as N shards on Slurm: OUT/slurm/shards.sbatch (a job array of `batch "
                                 "--shard K/N --resume`) and finish.sbatch (merge, with the whole-run fit); the batch's options follow");
  cmd->allow_extras();
  cmd->add_option("--shards", plan->shards, "Number of shards N (array tasks)")->required()->check(CLI::Range(1, 100000));
  cmd->add_option("--out", plan->out, "Output directory: OUT/slurm, OUT/shards/K, the merged outputs")->required();
  cmd->add_option("--store", plan->store, "One store all shards write (postgresql://...): no merge");
  cmd->add_option("--cpus-per-task", plan->cpus_per_task, "CPUs of each task; the batch runs as many --jobs")
      ->check(CLI::Range(1, 4096));
  cmd->add_option("--sbatch", plan->sbatch_options, "One more #SBATCH line for both scripts, e.g. --sbatch=--partition=cpu");
  cmd->add_option("--launcher", plan->launcher,
                  "Shell words each task's cadastre3d runs under, e.g. srun, or "
                  "'/usr/bin/time -v -a -o OUT/slurm/time-$SLURM_JOB_ID' ($K: the task's shard)");
  auto* sub = cmd->add_flag("--submit", *submit, "Submit the array and the finish job after it; prints their job ids");
  cmd->add_flag("--dry-run", "Write the scripts and print how to submit them (the default)")->excludes(sub);
  cmd->callback([plan, submit, cmd] {
    plan->out = fs::absolute(plan->out).lexically_normal().string();
    plan->batch_args = cmd->remaining();
    check_batch_options(plan->batch_args, plan->out + "/shards/1", *plan);
    std::error_code ec;
    plan->exe = fs::read_symlink("/proc/self/exe", ec).string();  // the tasks run this very build
    if (ec) plan->exe = "cadastre3d";
    plan->workdir = fs::current_path().string();
    const SlurmScripts s = write_slurm_scripts(*plan);
    std::cout << "array:  " << s.shards << "\nfinish: " << s.finish << "\nrerun:  " << s.rerun << " K  (a killed task)\n";
    if (!*submit)  // quoted: OUT may hold spaces
      std::cout << "submit: job=$(sbatch --parsable " << shell_quote(s.shards) << ") && sbatch --dependency=afterok:$job " << shell_quote(s.finish) << "\n";
    else {
      const SlurmJobs j = submit_slurm(s);
      std::cout << "shards: job " << j.shards << " (array 1-" << plan->shards << ")\nfinish: job " << j.finish << "\n";
    }
    exit_code() = kExitOk;
  });
}

}  // namespace c3d::cli
