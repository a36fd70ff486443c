#include <algorithm>
#include <filesystem>
#include <stdexcept>

#include "ifc_citygml/export.h"

namespace c3d {
namespace {

// OBJ and STEP write a file per parcel or building: a page is written whole.
class PerFileWriter : public ExportWriter {
 public:
  using Write = std::vector<std::string> (*)(const BatchModel&, const std::string&, std::vector<std::string>*);
  PerFileWriter(const std::string& dir, Write write, std::vector<std::string>* skipped)
      : dir_(dir), write_(write), skipped_(skipped) {
    std::filesystem::create_directories(dir);
  }
  void add(const BatchModel& page) override {
    for (auto& f : write_(page, dir_, skipped_)) files_.push_back(std::move(f));
  }
  std::vector<std::string> finish() override { return std::move(files_); }

 private:
  std::string dir_;
  Write write_;
  std::vector<std::string>* skipped_;
  std::vector<std::string> files_;
};

std::vector<std::string> obj_files(const BatchModel& m, const std::string& dir, std::vector<std::string>*) {
  return write_obj_per_parcel(m, dir);
}

std::vector<std::string> step_files(const BatchModel& m, const std::string& dir, std::vector<std::string>* skipped) {
  return write_step_per_building(m, dir, skipped);
}

void check_format_name(const std::string& f) {
  const auto& names = export_format_names();
  if (std::find(names.begin(), names.end(), f) == names.end())
    throw std::invalid_argument("unknown export format '" + f +
                                "' (use gml, gml3, cityjson, cityjsonseq, ifc, obj, step, 3dtiles)");
}

}  // namespace

const std::vector<std::string>& export_format_names() {
  static const std::vector<std::string> names{"gml", "gml3", "cityjson", "cityjsonseq",
                                                "ifc", "obj", "step", "3dtiles"};
  return names;
}

std::unique_ptr<ExportWriter> export_writer(const std::string& f, const BatchModel& header,
                                            const std::string& dir, std::vector<std::string>* skipped) {
  check_format_name(f);
  std::filesystem::create_directories(dir);
  auto path = [&](const char* name) { return (std::filesystem::path(dir) / name).string(); };
  if (f == "gml") return citygml_writer(header, path("buildings.gml"), 2);
  if (f == "gml3") return citygml_writer(header, path("buildings.citygml3.gml"), 3);
  if (f == "cityjson") return cityjson_writer(header, path("buildings.city.json"));
  if (f == "cityjsonseq") return cityjson_seq_writer(header, path("buildings.city.jsonl"));
  if (f == "ifc") return ifc_writer(header, path("buildings.ifc"));
  if (f == "obj") return std::make_unique<PerFileWriter>(path("obj"), obj_files, nullptr);
  if (f == "3dtiles") return tileset_writer(header, path("3dtiles"));
  return std::make_unique<PerFileWriter>(path("step"), step_files, skipped);
}

std::vector<std::string> export_formats(const BatchModel& model, const std::string& dir,
                                        const std::vector<std::string>& formats,
                                        std::vector<std::string>* skipped) {
  for (const auto& f : formats) check_format_name(f);  // all, before writing any
  std::filesystem::create_directories(dir);
  std::vector<std::string> out;
  for (const auto& f : formats) {
    auto w = export_writer(f, model, dir, skipped);
    w->add(model);
    for (auto& p : w->finish()) out.push_back(std::move(p));
  }
  return out;
}

}  // namespace c3d
