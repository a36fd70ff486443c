#pragma once
// Each sub-command lives in its own cli/cmd_<name>.cpp and registers itself here.
// Exit codes (documented in README): 0 ok, 1 bad input / failed command,
// 2 usage error, 3 batch finished but some parcels failed or are suspect.
#include <CLI/CLI.hpp>

#include "cadastre/batch/batch.h"

namespace c3d::cli {

constexpr int kExitOk = 0;
constexpr int kExitError = 1;
constexpr int kExitUsage = 2;
constexpr int kExitPartial = 3;

void register_info(CLI::App& app);
void register_sample(CLI::App& app);
void register_clip(CLI::App& app);
// parse_only: the options are checked, no batch runs (the Slurm runner checks its tasks' options).
void register_batch(CLI::App& app, bool parse_only = false);
void register_evaluate(CLI::App& app);
void register_report(CLI::App& app);
void register_export(CLI::App& app);
void register_validate(CLI::App& app);
void register_optimize(CLI::App& app);
void register_mesh(CLI::App& app);
void register_classify(CLI::App& app);
void register_merge(CLI::App& app);
void register_slurm(CLI::App& app);

// --store's check: an existing file, or a postgresql:// URL (checked on connecting).
inline const CLI::Validator existing_store(
    [](std::string& s) {
      if (s.rfind("postgresql://", 0) == 0 || s.rfind("postgres://", 0) == 0) return std::string();
      return CLI::ExistingFile(s);
    },
    "FILE or postgresql://URL");

// The batch's input options (cmd_batch.cpp): one parser for `batch` and for
// `merge`'s whole-run fit; `slurm` passes them on to merge by their group.
struct InputOptions {
  BatchInputs inputs;
  std::string config, device, id_field, model = C3D_DEFAULT_MODEL;  // device: the optimizer's
  bool optimize = false, classify = false, mesh = false;
  bool given() const { return !inputs.clouds.empty() || !inputs.parcels.empty(); }
};
inline const char* const kInputGroup = "Inputs";
void add_input_options(CLI::App* cmd, InputOptions& o, bool required);  // required: --cloud, --parcels
// The configuration the batch runs with (the file's, then the options'); sets inputs.classifier_model.
Config input_config(InputOptions& o);

// Set by a command's callback; returned by main.
int& exit_code();

}  // namespace c3d::cli
