/// @file random_streams.hpp
/// Independent, reproducible random streams derived from one run seed. Each consumer
/// (frame k's noise, the gyro, the fault layout...) gets its own std::mt19937_64 seeded
/// with a SplitMix64 hash of (seed, stream, index), so that rendering frame 7 alone gives
/// bit for bit the same image as rendering frames 0..7 in order, and the live sensors
/// reproduce the offline rawlog.
#pragma once
#include <cstdint>
#include <random>

namespace st {

/// SplitMix64 finaliser (Steele, Lea & Flood 2014): a bijective 64-bit mixer.
constexpr uint64_t splitMix64(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

/// Names of the streams (values are part of the reproducibility contract: never reorder).
enum class RandomStream : uint64_t {
  kFrameNoise = 1,
  kFrameClutter = 2,
  kFrameDrop = 3,
  kGyro = 4,
  kGyroInitialBias = 5,
  kFaultLayout = 6,
  kMissingStars = 7,
  kGyroFaults = 8,
};

/// Seed of one stream; `index` is e.g. the frame number.
constexpr uint64_t streamSeed(uint64_t seed, RandomStream stream, uint64_t index = 0) {
  return splitMix64(splitMix64(splitMix64(seed) ^ static_cast<uint64_t>(stream)) + index);
}

inline std::mt19937_64 makeRng(uint64_t seed, RandomStream stream, uint64_t index = 0) {
  return std::mt19937_64(streamSeed(seed, stream, index));
}

/// A uniform double in [0, 1) from a 64-bit hash (53 bits).
constexpr double hashToUnit(uint64_t h) { return static_cast<double>(h >> 11) * 0x1.0p-53; }

}  // namespace st
