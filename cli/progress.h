#pragma once
// A one-line progress bar on stderr for long work (only when stderr is a terminal,
// so logs and CI output stay clean).
#include <unistd.h>

#include <cstdio>
#include <string>

namespace c3d::cli {

class Progress {
 public:
  Progress(std::string label, size_t total, bool quiet)
      : label_(std::move(label)), total_(total), show_(!quiet && isatty(2)) {}
  void step() {
    ++done_;
    if (!show_) return;
    int width = 30, filled = total_ ? int(width * done_ / total_) : width;
    std::fprintf(stderr, "\r%s [%.*s%*s] %zu/%zu", label_.c_str(), filled,
                 "##############################", width - filled, "", done_, total_);
    std::fflush(stderr);
  }
  void done() {
    if (show_) std::fprintf(stderr, "\n");
  }

 private:
  std::string label_;
  size_t total_ = 0, done_ = 0;
  bool show_ = false;
};

}  // namespace c3d::cli
