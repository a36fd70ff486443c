#pragma once
// The one logger of the libraries. Library code never writes to stderr or reads
// the environment itself: it logs here, and the program that links it (the
// CLI, a test, a shard runner) sets the level and, if it wants, the sink.
#include <functional>
#include <string>

namespace c3d::log {

enum class Level { Debug, Info, Warn, Error, Off };

void set_level(Level level);  // default: Info
bool enabled(Level level);
// Where messages go (default: one line each on stderr). Calls are serialised.
void set_sink(std::function<void(Level, const std::string&)> sink);

void write(Level level, const std::string& message);
inline void debug(const std::string& m) { if (enabled(Level::Debug)) write(Level::Debug, m); }
inline void info(const std::string& m) { if (enabled(Level::Info)) write(Level::Info, m); }
inline void warn(const std::string& m) { if (enabled(Level::Warn)) write(Level::Warn, m); }
inline void error(const std::string& m) { if (enabled(Level::Error)) write(Level::Error, m); }

// printf-style formatting for the messages above.
std::string format(const char* fmt, ...) __attribute__((format(printf, 1, 2)));

}  // namespace c3d::log
