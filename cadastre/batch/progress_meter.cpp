#include "cadastre/batch/progress_meter.h"

#include <cstdio>

namespace c3d {

std::string ProgressMeter::update(const std::string& stage, size_t done, size_t total, bool* log_due) {
  if (stage != stage_) {
    stage_ = stage;
    t0_ = Clock::now();
    logged_s_ = logged_share_ = 0;
  }
  const double t = std::chrono::duration<double>(Clock::now() - t0_).count();
  share_ = total ? double(done) / double(total) : 1.0;
  *log_due = done >= total || t - logged_s_ >= kLogEveryS ||
             (share_ - logged_share_ >= kLogEveryShare && t - logged_s_ >= kLogGapS);
  if (*log_due) logged_s_ = t, logged_share_ = share_;
  char buf[96];
  if (done >= total) std::snprintf(buf, sizeof buf, "done in %.1f s", t);
  else if (done == 0) std::snprintf(buf, sizeof buf, "%.0f s", t);
  else std::snprintf(buf, sizeof buf, "%.0f s, about %.0f s left", t, t * double(total - done) / double(done));
  return stage + " " + std::to_string(done) + "/" + std::to_string(total) + " " + buf;
}

}  // namespace c3d
