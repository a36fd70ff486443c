// cadastre3d classify: a cloud labelled ground / roof / wall / other by the shipped
// Random Forest (core/classify); --train, --evaluate: cadastre/classify.
#include <malloc.h>

#include <fstream>
#include <iostream>
#include <memory>

#include "cadastre/classify/classify_files.h"
#include "cadastre/classify/cloud_evaluation.h"
#include "cadastre/classify/training.h"
#include "cli/commands.h"
#include "core/config/config.h"

namespace c3d::cli {
namespace {

struct ClassifyArgs {
  std::string cloud, out, dtm, config, cimahi, labelled, table;
  std::string model = C3D_DEFAULT_MODEL;
  bool train = false, evaluate = false;
};

void run_classify(const ClassifyArgs& a) {
  const Config cfg = a.config.empty() ? default_config() : load_config(a.config);
  // Blocks build and drop tables of a few MB: keep freed memory rather than refault
  // it from the kernel (a tenth of the command's CPU here; docs/classification.md).
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  classify_files(PointForest::load(a.model), cfg.classes, a.cloud, a.out, a.dtm, std::cout);
}

void print_table(const std::string& table, const std::string& path) {  // and write it to path, if any
  if (std::cout << table; !path.empty()) std::ofstream(path) << table;
}

// A labelled cloud judged as if it came unclassified (cloud_evaluation.h).
void run_cloud_evaluation(const ClassifyArgs& a) {
  const Config cfg = a.config.empty() ? default_config() : load_config(a.config);
  print_table(cloud_evaluation_text(evaluate_cloud_file(PointForest::load(a.model), a.cloud, cfg.classes, a.dtm), a.cloud),
              a.table);
}

void run_training(const ClassifyArgs& a) {
  TrainingOptions opt;
  opt.cimahi_dir = a.cimahi;
  opt.labelled_dir = a.labelled;
  if (a.evaluate && !a.labelled.empty()) {
    const Config cfg = a.config.empty() ? default_config() : load_config(a.config);
    return print_table(survey_scores_table(leave_one_survey_out(opt, cfg.classes)), a.table);
  }
  const TrainingData data = training_data(opt);
  PointForest forest;
  if (a.train) {
    forest = train_forest(data, opt);
    forest.save(a.out);
    std::cout << "model: " << a.out << "\n";
  } else {
    forest = PointForest::load(a.model);
  }
  std::vector<Evaluation> evals;
  for (const auto& set : data.held_out) evals.push_back(evaluate(forest, set));
  print_table(evaluation_table(evals), a.table);
}

}  // namespace

void register_classify(CLI::App& app) {
  auto a = std::make_shared<ClassifyArgs>();
  auto* cmd = app.add_subcommand(
      "classify", "Label a cloud's points ground / roof / wall / other with the shipped Random Forest; "
                  "--train rebuilds the model, --evaluate judges it (held-out data, or a labelled --cloud)");
  cmd->add_option("--cloud", a->cloud, "Point cloud to classify (LAS, LAZ, PLY, PCD, XYZ/CSV), or a folder of tiles");
  cmd->add_option("--out", a->out, "Output LAS, a folder for a folder of tiles, or the model file (--train)");
  cmd->add_option("--dtm", a->dtm, "Terrain model; default: from ground-class points, else by the SMRF ground filter");
  cmd->add_option("--model", a->model, "Classifier model")->capture_default_str();
  cmd->add_option("--config", a->config, "TOML config: its [classes] codes are written");
  cmd->add_flag("--train", a->train, "Train a model on the sample towns and Cimahi, write it to --out");
  cmd->add_flag("--evaluate", a->evaluate, "Precision and recall of --model: on the labelled --cloud as if it came "
                                           "unclassified (ground, building, vegetation), else on the held-out data");
  cmd->add_option("--cimahi", a->cimahi, "Cimahi data folder for --train / --evaluate");
  cmd->add_option("--labelled", a->labelled, "Folder of labelled LAS/LAZ surveys: trained on; with --evaluate, "
                                             "each left out in turn");
  cmd->add_option("--table", a->table, "Also write the evaluation table (Markdown) here");
  cmd->callback([a] {
    if (a->evaluate && !a->train && !a->cloud.empty()) return run_cloud_evaluation(*a);
    if (a->train && a->out.empty()) throw CLI::ValidationError("--train", "needs --out MODEL");
    if (a->train || a->evaluate) return run_training(*a);
    if (a->cloud.empty() || a->out.empty()) throw CLI::ValidationError("classify", "needs --cloud IN and --out OUT.las");
    run_classify(*a);
  });
}

}  // namespace c3d::cli
