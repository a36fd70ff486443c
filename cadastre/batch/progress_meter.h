#pragma once
// Paces and words the progress of a batch's stages (BatchSettings::progress,
// OutputProgress) for a person: the CLI shows it as a bar on a terminal and
// as log lines otherwise.
#include <chrono>
#include <string>

namespace c3d {

class ProgressMeter {
 public:
  static constexpr double kLogEveryS = 10;       // a log quiet for longer looks like a hang
  static constexpr double kLogEveryShare = 0.1;  // ten lines for a long stage, not thousands
  static constexpr double kLogGapS = 1;          // a short stage: only its last line

  // `done` of `total` steps of `stage` (a new name starts a new stage): the
  // words, e.g. "reconstruct 40/100 12 s, about 18 s left", and in *log_due
  // whether a log line is due now (every kLogEveryS, or kLogEveryShare of the
  // stage after kLogGapS, and at its end).
  std::string update(const std::string& stage, size_t done, size_t total, bool* log_due);
  double share() const { return share_; }  // of the current stage, 0..1
  void end_stage() { stage_.clear(); }

 private:
  using Clock = std::chrono::steady_clock;
  std::string stage_;
  Clock::time_point t0_ = Clock::now();
  double logged_s_ = 0, logged_share_ = 0, share_ = 0;
};

}  // namespace c3d
