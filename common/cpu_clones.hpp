/// @file cpu_clones.hpp
/// ST_AVX2_CLONES: compile a hot pixel loop twice (AVX2 and the baseline) and let the dynamic
/// loader pick one for the CPU (GCC's target_clones, an ifunc). Off under ThreadSanitizer:
/// an ifunc resolver runs while the loader relocates the program, before the TSan runtime is
/// up, and its instrumented code crashes the program before main() (scripts/tsan.sh).
#pragma once

#if defined(__GNUC__) && defined(__x86_64__) && !defined(__SANITIZE_THREAD__)
#define ST_AVX2_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define ST_AVX2_CLONES
#endif
