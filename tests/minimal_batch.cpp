// A whole parcel batch from a program that links the library, without the CLI:
//   minimal_batch CLOUD PARCELS DTM OUT
#include <cstdio>
#include <string>

#include "cadastre/batch/outputs.h"
#include "cadastre/batch/store_sink.h"

int main(int argc, char** argv) {
  if (argc != 5) return std::fprintf(stderr, "usage: minimal_batch CLOUD PARCELS DTM OUT\n"), 2;
  const c3d::BatchInputs inputs{{argv[1]}, {}, argv[2], argv[3]};
  const c3d::Config cfg = c3d::default_config();
  c3d::StoreSink store(std::string(argv[4]) + "/cadastre.gpkg");
  const c3d::BatchReport report = c3d::run_batch(inputs, cfg, store);
  c3d::write_outputs(report, store.path(), argv[4], cfg, {"cityjson"});
  c3d::mark_run_finished(store.path());  // last: every output is in place
  std::printf("%zu parcels, %zu failed\n", report.parcels, report.failed);
  return report.failed > 0 ? 3 : 0;
}
