#pragma once
// Deterministic randomness for the simulator. Everything random is a hash of (seed, what, where),
// never a shared generator's state, so results do not depend on thread count or call order.

#include <cmath>
#include <cstdint>

namespace artemis::sim::detail {

inline std::uint64_t mix64(std::uint64_t x) {  // SplitMix64 finaliser
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

inline std::uint64_t hash(std::uint64_t a, std::uint64_t b) {
  return mix64(a ^ mix64(b));
}
inline std::uint64_t hash(std::uint64_t a, std::uint64_t b, std::uint64_t c) {
  return hash(hash(a, b), c);
}
inline std::uint64_t hash(std::uint64_t a, std::uint64_t b, std::uint64_t c, std::uint64_t d) {
  return hash(hash(a, b, c), d);
}

// Uniform in [0, 1) from the top 53 bits.
inline double unit(std::uint64_t h) {
  return static_cast<double>(h >> 11) * 0x1.0p-53;
}

// Standard normal from two hashes (Box-Muller).
inline double gaussian(std::uint64_t h) {
  const double u1 = unit(h) + 0x1.0p-54;  // never 0
  const double u2 = unit(mix64(h));
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
}

// A small sequential generator for scene layout (one per generated scene).
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : state_(mix64(seed)) {}
  std::uint64_t next() { return state_ = mix64(state_); }
  double uniform() { return unit(next()); }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  int integer(int lo, int hi_inclusive) {
    return lo + static_cast<int>(uniform() * static_cast<double>(hi_inclusive - lo + 1));
  }
  bool chance(double p) { return uniform() < p; }

 private:
  std::uint64_t state_;
};

// Value noise on an integer lattice, smoothly interpolated, in [0, 1].
inline double latticeValue(std::uint64_t seed, std::int64_t x, std::int64_t y, std::int64_t z) {
  return unit(hash(seed, static_cast<std::uint64_t>(x), static_cast<std::uint64_t>(y), static_cast<std::uint64_t>(z)));
}

inline double smooth(double t) {
  return t * t * (3.0 - 2.0 * t);
}

inline double valueNoise(std::uint64_t seed, double x, double y, double z) {
  const double fx = std::floor(x);
  const double fy = std::floor(y);
  const double fz = std::floor(z);
  const auto ix = static_cast<std::int64_t>(fx);
  const auto iy = static_cast<std::int64_t>(fy);
  const auto iz = static_cast<std::int64_t>(fz);
  const double tx = smooth(x - fx);
  const double ty = smooth(y - fy);
  const double tz = smooth(z - fz);
  double c[2][2];
  for (int dz = 0; dz < 2; ++dz) {
    for (int dy = 0; dy < 2; ++dy) {
      const double a = latticeValue(seed, ix, iy + dy, iz + dz);
      const double b = latticeValue(seed, ix + 1, iy + dy, iz + dz);
      c[dz][dy] = a + (b - a) * tx;
    }
  }
  const double lo = c[0][0] + (c[0][1] - c[0][0]) * ty;
  const double hi = c[1][0] + (c[1][1] - c[1][0]) * ty;
  return lo + (hi - lo) * tz;
}

// Fractal sum of `octaves` value-noise layers at `frequency` (cycles per metre), in [0, 1].
inline double fbm(std::uint64_t seed, double x, double y, double z, double frequency, int octaves) {
  double sum = 0.0;
  double amplitude = 0.5;
  double norm = 0.0;
  for (int i = 0; i < octaves; ++i) {
    sum += amplitude * valueNoise(seed + static_cast<std::uint64_t>(i), x * frequency, y * frequency, z * frequency);
    norm += amplitude;
    amplitude *= 0.5;
    frequency *= 2.0;
  }
  return sum / norm;
}

// Integer cell index of x for cells of size `cell`.
inline std::int64_t cellOf(double x, double cell) {
  return static_cast<std::int64_t>(std::floor(x / cell));
}

}  // namespace artemis::sim::detail
