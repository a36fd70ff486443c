#pragma once
// A one-line progress bar on stderr for long work (only when stderr is a terminal,
// so logs and CI output stay clean).
#include <unistd.h>

#include <cstdio>
#include <string>

namespace c3d::cli {

class Progress {
 public:
  Progress(std::string label, bool quiet) : label_(std::move(label)), show_(!quiet && isatty(2)) {}
  void show(size_t done, size_t total) {
    if (!show_) return;
    shown_ = true;
    int width = 30, filled = total ? int(width * done / total) : width;
    std::fprintf(stderr, "\r%s [%.*s%*s] %zu/%zu", label_.c_str(), filled,
                 "##############################", width - filled, "", done, total);
    std::fflush(stderr);
  }
  void done() {
    if (shown_) std::fprintf(stderr, "\n");
  }

 private:
  std::string label_;
  bool show_ = false, shown_ = false;
};

}  // namespace c3d::cli
