/// @file log.hpp
/// The process-wide verbosity and the program's messages on stderr, printf-style:
///   st::log::info("loading %s", path);   // "[catalog] loading stars.dat"
/// Every line starts with the command's tag ("[solve] ") so that a user piping several
/// commands together can tell who spoke. stdout stays for results (tables, JSON).
///
/// Levels, set once by main from -q / -v (the policy lives here, not in each command):
///  - quiet (-q):   errors and warnings only; no info, no progress bars.
///  - normal:       errors, warnings, info, progress bars.
///  - verbose (-v): also debug lines (and OpenCV's own warnings, see app/cli/verbosity.cpp).
/// Warnings stay on under -q on purpose: a warning says a result may be wrong (a database
/// too small for the image, frames dropped), and -q is for scripts that still need to know.
/// Errors are always shown.
///
/// Thread-safe: each message is formatted first and written in one call under a lock, so
/// lines from worker threads never interleave. Call setVerbosity/setTag before threads start.
///
/// The namespace is `st::log`: inside namespace st, write `std::log(x)` for the logarithm in
/// a file that includes this header (an unqualified `log(x)` would name this namespace).
#pragma once
#include <string>

#if defined(__GNUC__)
#define ST_PRINTF_FORMAT(fmt_index, first_arg) __attribute__((format(printf, fmt_index, first_arg)))
#else
#define ST_PRINTF_FORMAT(fmt_index, first_arg)
#endif

namespace st::log {

enum class Verbosity { kQuiet = -1, kNormal = 0, kVerbose = 1 };

void setVerbosity(Verbosity v);
Verbosity verbosity();
/// True under -q: info lines and progress bars are off.
bool quiet();
/// True under -v: debug lines are on.
bool verbose();

/// The tag printed in brackets before every line, e.g. "solve" -> "[solve] "; "" for none.
void setTag(const std::string& tag);

/// Progress and facts a user may want to see (off under -q).
void info(const char* fmt, ...) ST_PRINTF_FORMAT(1, 2);
/// Something that may make a result wrong or incomplete ("warning: " after the tag).
void warn(const char* fmt, ...) ST_PRINTF_FORMAT(1, 2);
/// Details for finding out why (only with -v).
void debug(const char* fmt, ...) ST_PRINTF_FORMAT(1, 2);
/// A failure ("error: " after the tag); always shown.
void error(const char* fmt, ...) ST_PRINTF_FORMAT(1, 2);

}  // namespace st::log
