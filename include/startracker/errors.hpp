/// @file errors.hpp
/// The three kinds of failure (see STYLE-EXAMPLES.md §7):
///  - bugs: assert;
///  - bad configuration or input (file, key, value): throw InputError at the I/O edge; the
///    CLI turns it into exit code 2;
///  - a processing failure on valid input (an image that cannot be solved): library code
///    returns a status; the CLI exits 1. ProcessingError exists for the rare case where a
///    library cannot return one (e.g. a rawlog that breaks half way).
#pragma once
#include <stdexcept>
#include <string>

namespace st {

/// Bad input or configuration. The message must name the file, key or value.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The edge's throwing wrapper of an options struct's validation, `bool isValid(std::string*
/// why) const` (every options struct of a stage has that one signature; `why` names the
/// struct and the field). Library code validates once, at construction, and reports; only
/// the edge (CLI, .ini reader, a convenience wrapper) throws.
template <class Options>
void requireValid(const Options& options) {
  std::string why;
  if (!options.isValid(&why)) throw InputError(why);
}

/// Valid input that could not be processed.
class ProcessingError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace st
