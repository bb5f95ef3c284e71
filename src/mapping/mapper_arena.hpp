#pragma once
// Internal to the mapping module: the mapper's task arena (its thread count is params.threads),
// shared by the files that define the mapper's members.

#include <tbb/task_arena.h>

#include "artemis/mapping/mapper.hpp"

namespace artemis::mapping {

struct Mapper::Arena {
  explicit Arena(int threads) : arena(threads > 0 ? threads : tbb::task_arena::automatic) {}
  tbb::task_arena arena;
};

}  // namespace artemis::mapping
