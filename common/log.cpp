#include "common/log.hpp"

#include <atomic>
#include <cstdarg>
#include <cstdio>
#include <mutex>

namespace st::log {
namespace {

std::atomic<int> g_verbosity{static_cast<int>(Verbosity::kNormal)};
std::string g_tag;  // written once by main before any thread starts
std::mutex g_write_mu;

void emit(const char* kind, const char* fmt, va_list args) {
  va_list copy;
  va_copy(copy, args);
  const int n = std::vsnprintf(nullptr, 0, fmt, copy);
  va_end(copy);
  std::string body(n > 0 ? static_cast<std::size_t>(n) : 0, '\0');
  if (n > 0) std::vsnprintf(body.data(), body.size() + 1, fmt, args);
  std::string line;
  if (!g_tag.empty()) line = "[" + g_tag + "] ";
  line += kind;
  line += body;
  if (line.empty() || line.back() != '\n') line += '\n';
  const std::lock_guard<std::mutex> lock(g_write_mu);
  std::fputs(line.c_str(), stderr);
  std::fflush(stderr);
}

}  // namespace

void setVerbosity(Verbosity v) { g_verbosity = static_cast<int>(v); }
Verbosity verbosity() { return static_cast<Verbosity>(g_verbosity.load()); }
bool quiet() { return verbosity() == Verbosity::kQuiet; }
bool verbose() { return verbosity() == Verbosity::kVerbose; }
void setTag(const std::string& tag) { g_tag = tag; }

#define ST_LOG_EMIT(kind)     \
  va_list args;               \
  va_start(args, fmt);        \
  emit(kind, fmt, args);      \
  va_end(args)

void info(const char* fmt, ...) {
  if (quiet()) return;
  ST_LOG_EMIT("");
}

void warn(const char* fmt, ...) { ST_LOG_EMIT("warning: "); }

void debug(const char* fmt, ...) {
  if (!verbose()) return;
  ST_LOG_EMIT("debug: ");
}

void error(const char* fmt, ...) { ST_LOG_EMIT("error: "); }

#undef ST_LOG_EMIT

}  // namespace st::log
