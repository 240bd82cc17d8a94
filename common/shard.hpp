/// @file shard.hpp
/// `--shard i/N`: run `i` of `N` independent parts of one job (a Slurm array task, say). Part
/// i takes items i, i + N, i + 2N, ... of the whole, so the parts of a list sorted in time
/// (a night's frames, a Monte Carlo's trials) are alike in size and in difficulty, and each
/// item's result does not depend on N.
#pragma once
#include <cstddef>
#include <string>

namespace st {

struct Shard {
  int index = 0;  ///< i, 0-based (Slurm's SLURM_ARRAY_TASK_ID for --array=0-(N-1))
  int count = 1;  ///< N (SLURM_ARRAY_TASK_COUNT)

  /// Parses "i/N" with 0 <= i < N <= 1e6. InputError naming `flag` and the text otherwise.
  static Shard parse(const std::string& text, const std::string& flag = "--shard");
  /// True when item `k` of the whole belongs to this part.
  bool takes(std::size_t k) const { return k % static_cast<std::size_t>(count) == std::size_t(index); }
  bool whole() const { return count == 1; }
  /// "i/N".
  std::string label() const { return std::to_string(index) + "/" + std::to_string(count); }
};

}  // namespace st
