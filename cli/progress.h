#pragma once
// The batch's progress on stderr (words and pace: ProgressMeter): a bar on a
// terminal, log lines otherwise, so logs and CI output stay short.
#include <unistd.h>

#include <cstdio>
#include <string>

#include "cadastre/batch/progress_meter.h"

namespace c3d::cli {

class Progress {
 public:
  explicit Progress(bool quiet) : quiet_(quiet), tty_(isatty(2) != 0) {}
  ~Progress() { done(); }

  void show(const std::string& stage, size_t done, size_t total) {
    if (quiet_) return;
    bool log_due = false;
    const std::string text = meter_.update(stage, done, total, &log_due);
    if (!tty_) {
      if (log_due) std::fprintf(stderr, "cadastre3d: %s\n", text.c_str());
      return;
    }
    const int width = 30, filled = int(width * meter_.share());
    std::fprintf(stderr, "\r[%.*s%*s] %s   ", filled, "##############################", width - filled, "",
                 text.c_str());
    if (done >= total) std::fprintf(stderr, "\n");
    std::fflush(stderr);
  }
  void done() { meter_.end_stage(); }

 private:
  bool quiet_, tty_;
  ProgressMeter meter_;
};

}  // namespace c3d::cli
