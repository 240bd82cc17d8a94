/// @file check.hpp
/// ST_ASSERT: the failure kind "bug" of common/errors.hpp. A broken internal invariant (a
/// caller violating a documented precondition, a state that cannot happen) aborts with the
/// condition, file and line. Active in debug builds and wherever ST_ENABLE_ASSERTS is defined:
/// the CMake option ST_ASSERTS (default ON) defines it for every project target, tests
/// included; -DST_ASSERTS=OFF compiles it out of a release build. Keep it off per-pixel
/// loops. Never use it for bad input: that is InputError, at the edge.
#pragma once

#if !defined(NDEBUG) || defined(ST_ENABLE_ASSERTS)
#include <cstdio>
#include <cstdlib>
#define ST_ASSERT(cond)                                                               \
  do {                                                                                \
    if (!(cond)) {                                                                    \
      std::fprintf(stderr, "%s:%d: assertion failed: %s\n", __FILE__, __LINE__, #cond); \
      std::abort();                                                                   \
    }                                                                                 \
  } while (0)
#else
#define ST_ASSERT(cond) \
  do {                  \
  } while (0 && (cond))
#endif
