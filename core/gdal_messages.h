#pragma once
// GDAL, OGR and PROJ report problems through CPLError, which by default prints
// "ERROR 1: ..." lines on stderr, often a dozen for one bad file. While a
// GdalMessages lives, this thread's messages are collected instead (and go to
// the debug log); the reader folds the last one into its one-line InputError.
//
//   GdalMessages gdal;
//   try { ...read... } catch (const InputError& e) { throw gdal.fold(e); }
#include <string>
#include <vector>

#include "core/error.h"

namespace c3d {

// Outside any GdalMessages, GDAL's messages go to the debug log too, never
// straight to stderr: the one-line errors say what went wrong (the CLI calls
// this once at start).
void send_gdal_messages_to_debug_log();

class GdalMessages {
 public:
  GdalMessages();
  ~GdalMessages();
  GdalMessages(const GdalMessages&) = delete;
  GdalMessages& operator=(const GdalMessages&) = delete;

  // How many failures (CE_Failure or worse) GDAL reported so far.
  size_t failures() const { return failures_; }
  // How many messages (warnings and failures) GDAL reported so far.
  size_t count() const { return count_; }
  // The last failure GDAL reported (else its last warning); "" when none.
  std::string last() const;
  // e with "GDAL: <last>" appended, unless there is none or e already says it.
  InputError fold(const InputError& e) const;
  // "problem (GDAL: <last>)", or the problem alone when GDAL said nothing.
  std::string with_last(const std::string& problem) const;
  // Called by the handler GDAL calls.
  void record(bool failure, const std::string& text);

 private:
  struct Message {
    bool failure;
    std::string text;
  };
  std::vector<Message> messages_;
  size_t failures_ = 0, count_ = 0;
};

}  // namespace c3d
