#include "cadastre/batch/slurm.h"

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "core/error.h"

namespace fs = std::filesystem;

namespace c3d {
namespace {

// Exit status of a batch that finished with failed or suspect parcels
// (cli/commands.h kExitPartial): a done task, so the finish job still runs.
constexpr int kBatchPartialExit = 3;

std::string slurm_dir(const std::string& out) { return (fs::path(out) / "slurm").string(); }

std::string shard_out(const SlurmPlan& p, const std::string& k) {
  return shell_quote((fs::path(p.out) / "shards").string() + "/") + k;
}

// A value of a #SBATCH line as sbatch reads it: in double quotes, with '"'
// and '\' escaped by '\' (spaces otherwise end the value, and an unquoted
// value with a space made sbatch refuse the script).
std::string sbatch_quote(const std::string& text) {
  std::string q = "\"";
  for (char c : text) q += c == '"' || c == '\\' ? std::string("\\") + c : std::string(1, c);
  return q + "\"";
}

// A path as an --output pattern: its own '%' kept ('%%'), the log's name's
// patterns (%a) left to Slurm.
std::string output_pattern(const std::string& dir, const std::string& log) {
  std::string s;
  for (char c : dir) s += c == '%' ? std::string("%%") : std::string(1, c);
  return s + "/" + log;
}

std::string header(const SlurmPlan& p, const std::string& name, const std::string& log) {
  std::string s = "#!/bin/bash\n#SBATCH --job-name=" + name + "\n#SBATCH --chdir=" + sbatch_quote(p.workdir) +
                  "\n#SBATCH --output=" + sbatch_quote(output_pattern(slurm_dir(p.out), log)) + "\n";
  if (p.cpus_per_task > 0) s += "#SBATCH --cpus-per-task=" + std::to_string(p.cpus_per_task) + "\n";
  for (const auto& o : p.sbatch_options) s += "#SBATCH " + o + "\n";
  return s;
}

// The command line's start: the launcher as written (shell text, so $K or
// $SLURM_JOB_ID in it expand in the task), then the quoted cadastre3d.
std::string run_exe(const SlurmPlan& p) {
  return (p.launcher.empty() ? "" : p.launcher + " ") + shell_quote(p.exe);
}

std::string shards_script(const SlurmPlan& p) {
  const std::string n = std::to_string(p.shards);
  std::string s = header(p, "c3d-shards", "shard-%a.log");
  s += "#SBATCH --array=1-" + n + "\n"
       "# Written by `cadastre3d slurm`: task K models shard K/" + n + " of the parcels.\n"
       "# A killed task reruns with  " + shell_quote(slurm_dir(p.out) + "/rerun.sh") +
       " K  (or sbatch --array=K this file):\n"
       "# --resume keeps the parcels it stored, so nothing is written twice.\n"
       "set -u\nK=$SLURM_ARRAY_TASK_ID\n" + run_exe(p) + " batch";
  for (const auto& a : p.batch_args) s += " " + shell_quote(a);
  s += " --out " + shard_out(p, "$K") + " --shard $K/" + n + " --resume";
  bool jobs = false;  // the user's --jobs, else the CPUs Slurm gave the task
  for (const auto& a : p.batch_args) jobs = jobs || a == "--jobs" || a.rfind("--jobs=", 0) == 0;
  if (!jobs) s += " --jobs ${SLURM_CPUS_PER_TASK:-1}";
  if (!p.store.empty()) s += " --store " + shell_quote(p.store);
  s += "\nrc=$?\n# " + std::to_string(kBatchPartialExit) +
       ": done, some parcels failed or suspect (in the store): the task is done\n"
       "[ $rc -eq " + std::to_string(kBatchPartialExit) + " ] && exit 0\nexit $rc\n";
  return s;
}

std::string finish_script(const SlurmPlan& p) {
  std::string s = header(p, "c3d-finish", "finish.log") + "# Written by `cadastre3d slurm`: runs after every shard task.\nset -e\n";
  const std::string formats = p.formats.empty() ? "" : " --formats " + shell_quote(p.formats);
  s += "exec " + run_exe(p) + " merge --out " + shell_quote(p.out) + " --overwrite" + formats;
  for (const auto& a : p.input_args) s += " " + shell_quote(a);  // the whole-run fit's inputs
  if (!p.store.empty()) return s + " --store " + shell_quote(p.store) + "\n";  // one store: nothing to merge
  for (int k = 1; k <= p.shards; ++k) s += " " + shard_out(p, std::to_string(k)) + "/cadastre.gpkg";
  return s + "\n";
}

std::string rerun_script(const SlurmPlan& p) {
  return "#!/bin/bash\n"
         "# Reruns shard tasks (a killed or failed one) and the finish step after them:\n"
         "#   " + shell_quote(slurm_dir(p.out) + "/rerun.sh") + " K [K...]\n"
         "# The tasks --resume: parcels already stored stay and are not written twice.\n"
         "set -euo pipefail\ncd \"$(dirname \"$0\")\"\n"
         "[ $# -ge 1 ] || { echo \"usage: $0 K [K...]\" >&2; exit 2; }\n"
         "ks=$(IFS=,; echo \"$*\")\n"
         "job=$(sbatch --parsable --array=\"$ks\" shards.sbatch); job=${job%%;*}\n"
         "if [ -f finish.jobid ]; then scancel \"$(cat finish.jobid)\" 2>/dev/null || true; fi\n"
         "# After the rerun, and after whatever is left of the first array.\n"
         "dep=afterok:$job\n"
         "if [ -f shards.jobid ]; then dep=$dep,afterany:$(cat shards.jobid); fi\n"
         "fin=$(sbatch --parsable --dependency=\"$dep\" finish.sbatch); fin=${fin%%;*}\n"
         "echo \"$fin\" > finish.jobid\n"
         "echo \"shards $ks: job $job; finish: job $fin\"\n";
}

void write_executable(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary);
  f << text;
  if (!f.flush()) throw InputError(path, "cannot write");
  f.close();
  fs::permissions(path, fs::perms::owner_exec | fs::perms::group_exec | fs::perms::others_exec, fs::perm_options::add);
}

// Runs sbatch --parsable ARGS and returns the job id it prints.
std::string sbatch(const std::string& args, const std::string& script) {
  const std::string cmd = "sbatch --parsable " + args + " " + shell_quote(script) + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) throw InputError(script, "cannot run sbatch");
  std::string out;
  char buf[256];
  while (fgets(buf, sizeof buf, pipe)) out += buf;
  const int rc = pclose(pipe);
  while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
  if (rc != 0 || out.empty() || out.find_first_not_of("0123456789;") != std::string::npos)
    throw InputError(script, "sbatch failed: " + out);
  return out.substr(0, out.find(';'));  // "id;cluster" on a federation
}

void write_text(const std::string& path, const std::string& text) {
  std::ofstream f(path);
  f << text << "\n";
  if (!f.flush()) throw InputError(path, "cannot write");
}

// The text with its control characters shown as C escapes (\n, \x1b), for
// a one-line message.
std::string visible(const std::string& text) {
  std::string s;
  for (unsigned char c : text) {
    if (c == '\n') s += "\\n";
    else if (c == '\r') s += "\\r";
    else if (c == '\t') s += "\\t";
    else if (c < 0x20 || c == 0x7f) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", c);
      s += hex;
    } else s += char(c);
  }
  return s;
}

// Every text the scripts hold, free of control characters: a newline in a
// path ends a #SBATCH line or a comment, and what follows runs as a command.
void refuse_control_characters(const SlurmPlan& p) {
  std::vector<std::pair<std::string, std::string>> texts = {
      {"cadastre3d", p.exe}, {"the working folder", p.workdir}, {"--out", p.out}, {"--store", p.store},
      {"--formats", p.formats}, {"--launcher", p.launcher}};
  for (const auto& a : p.batch_args) texts.emplace_back("a batch option", a);
  for (const auto& a : p.input_args) texts.emplace_back("a batch option", a);
  for (const auto& o : p.sbatch_options) texts.emplace_back("--sbatch", o);
  for (const auto& [what, text] : texts)
    for (unsigned char c : text)
      if (c < 0x20 || c == 0x7f)
        throw InputError(visible(text), what + " holds a control character (" + visible(std::string(1, char(c))) +
                                            "): refused in a Slurm script");
}

}  // namespace

std::string shell_quote(const std::string& text) {
  std::string q = "'";
  for (char c : text) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

SlurmScripts write_slurm_scripts(const SlurmPlan& plan) {
  refuse_control_characters(plan);
  const std::string dir = slurm_dir(plan.out);
  fs::create_directories(dir);
  fs::create_directories(fs::path(plan.out) / "shards");
  SlurmScripts s{dir + "/shards.sbatch", dir + "/finish.sbatch", dir + "/rerun.sh"};
  write_executable(s.shards, shards_script(plan));
  write_executable(s.finish, finish_script(plan));
  write_executable(s.rerun, rerun_script(plan));
  return s;
}

SlurmJobs submit_slurm(const SlurmScripts& scripts) {
  SlurmJobs j;
  j.shards = sbatch("", scripts.shards);
  j.finish = sbatch("--dependency=afterok:" + j.shards, scripts.finish);
  const fs::path dir = fs::path(scripts.shards).parent_path();
  write_text((dir / "shards.jobid").string(), j.shards);
  write_text((dir / "finish.jobid").string(), j.finish);
  return j;
}

}  // namespace c3d
