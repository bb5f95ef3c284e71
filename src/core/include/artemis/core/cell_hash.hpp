#pragma once
// Hash of an integer grid cell (a voxel key) for open-addressing tables: SplitMix64's finaliser
// over the packed coordinates, well spread in the low bits a power-of-two table keeps.

#include <cstdint>

namespace artemis {

inline std::uint64_t hashCell(std::int32_t x, std::int32_t y, std::int32_t z) {
  std::uint64_t h = (static_cast<std::uint64_t>(static_cast<std::uint32_t>(x)) << 42) ^
                    (static_cast<std::uint64_t>(static_cast<std::uint32_t>(y)) << 21) ^
                    static_cast<std::uint64_t>(static_cast<std::uint32_t>(z));
  h += 0x9E3779B97F4A7C15ull;
  h = (h ^ (h >> 30)) * 0xBF58476D1CE4E5B9ull;
  h = (h ^ (h >> 27)) * 0x94D049BB133111EBull;
  return h ^ (h >> 31);
}

}  // namespace artemis
