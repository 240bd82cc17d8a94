// Template part of fuzz_io.hpp.
#pragma once
#include <cstdio>
#include <cstdlib>

#include "common/errors.hpp"

namespace st::fuzz {

template <class F>
void refuseOnlyWithInputError(const std::string& path, F&& parse) {
  try {
    parse();
  } catch (const InputError& e) {
    // The project's contract (common.md): a refusal names the file it refuses.
    const std::string what = e.what();
    if (what.find(path) == std::string::npos) {
      std::fprintf(stderr, "fuzz finding: InputError without the file name '%s': %s\n",
                   path.c_str(), what.c_str());
      std::abort();
    }
  }
}

}  // namespace st::fuzz
