#include "core/log.h"

#include <atomic>
#include <cstdarg>
#include <cstdio>
#include <mutex>

namespace c3d::log {
namespace {

std::atomic<int> g_level{int(Level::Info)};
std::mutex g_mutex;

std::function<void(Level, const std::string&)>& sink() {
  static std::function<void(Level, const std::string&)> s = [](Level, const std::string& m) {
    std::fprintf(stderr, "%s\n", m.c_str());
  };
  return s;
}

}  // namespace

void set_level(Level level) { g_level = int(level); }

bool enabled(Level level) { return level != Level::Off && int(level) >= g_level.load(); }

void set_sink(std::function<void(Level, const std::string&)> s) {
  std::lock_guard<std::mutex> lock(g_mutex);
  sink() = std::move(s);
}

void write(Level level, const std::string& message) {
  std::lock_guard<std::mutex> lock(g_mutex);
  sink()(level, message);
}

std::string format(const char* fmt, ...) {
  va_list args;
  va_start(args, fmt);
  va_list copy;
  va_copy(copy, args);
  const int n = std::vsnprintf(nullptr, 0, fmt, copy);
  va_end(copy);
  std::string out(n > 0 ? size_t(n) : 0, '\0');
  if (n > 0) std::vsnprintf(out.data(), out.size() + 1, fmt, args);
  va_end(args);
  return out;
}

}  // namespace c3d::log
