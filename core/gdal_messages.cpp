#include "core/gdal_messages.h"

#include <cpl_error.h>

#include "core/log.h"

namespace c3d {

namespace {

void handler(CPLErr level, CPLErrorNum code, const char* text) {
  if (level == CE_Debug) return;
  const std::string message = text ? text : "";
  log::debug("GDAL " + std::string(level >= CE_Failure ? "error " : "warning ") + std::to_string(code) + ": " +
             message);
  if (auto* self = static_cast<GdalMessages*>(CPLGetErrorHandlerUserData())) self->record(level >= CE_Failure, message);
}

}  // namespace

void send_gdal_messages_to_debug_log() { CPLSetErrorHandlerEx(&handler, nullptr); }

GdalMessages::GdalMessages() { CPLPushErrorHandlerEx(&handler, this); }

GdalMessages::~GdalMessages() { CPLPopErrorHandler(); }

void GdalMessages::record(bool failure, const std::string& text) {
  constexpr size_t kKept = 100;  // a broken file can raise thousands; the last ones matter
  if (messages_.size() == kKept) messages_.erase(messages_.begin());
  std::string line;  // one line, whatever the driver wrote (PostgreSQL's run over three)
  for (char c : text) {
    const bool breaks = c == '\n' || c == '\r' || c == '\t';
    if (!breaks) line += c;
    else if (!line.empty() && line.back() != ' ') line += ' ';
  }
  while (!line.empty() && line.back() == ' ') line.pop_back();
  messages_.push_back({failure, line});
  failures_ += failure;
  ++count_;
}

std::string GdalMessages::last() const {
  for (auto it = messages_.rbegin(); it != messages_.rend(); ++it)
    if (it->failure) return it->text;
  return messages_.empty() ? std::string() : messages_.back().text;
}

InputError GdalMessages::fold(const InputError& e) const {
  const std::string said = last();
  if (said.empty() || std::string(e.what()).find(said) != std::string::npos) return e;
  return e.appended("GDAL: " + said);
}

std::string GdalMessages::with_last(const std::string& problem) const {
  const std::string said = last();
  return said.empty() || problem.find(said) != std::string::npos ? problem : problem + " (GDAL: " + said + ")";
}

}  // namespace c3d
