// A small deterministic random number generator (xoshiro256**, seeded through splitmix64)
// with its own uniform and normal draws, so that a seed gives the same scenario, scans and
// log bytes with any standard library. Independent streams (world, sensor, odometry) come
// from one seed and a stream number, so that changing one never shifts another.
#pragma once

#include <cmath>
#include <cstdint>

namespace freespace::sim {

class Rng {
 public:
  explicit Rng(std::uint64_t seed, std::uint64_t stream = 0) {
    std::uint64_t x = seed ^ (0x9E3779B97F4A7C15ull * (stream + 1));
    for (std::uint64_t& s : state_) s = SplitMix(&x);
  }

  std::uint64_t Next() {
    const std::uint64_t result = Rotl(state_[1] * 5, 7) * 9;
    const std::uint64_t t = state_[1] << 17;
    state_[2] ^= state_[0];
    state_[3] ^= state_[1];
    state_[1] ^= state_[2];
    state_[0] ^= state_[3];
    state_[2] ^= t;
    state_[3] = Rotl(state_[3], 45);
    return result;
  }

  // Uniform in [0, 1), 53 random bits.
  double Uniform() { return double(Next() >> 11) * 0x1.0p-53; }
  // Uniform in [a, b).
  double Uniform(double a, double b) { return a + (b - a) * Uniform(); }
  // Uniform integer in [lo, hi].
  int UniformInt(int lo, int hi) {
    return lo + int(Next() % std::uint64_t(std::int64_t(hi) - lo + 1));
  }
  bool Bernoulli(double p) { return Uniform() < p; }
  // Standard normal (Box-Muller; one draw per call keeps the stream simple).
  double Normal() {
    const double u = 1.0 - Uniform();  // (0, 1]
    const double v = Uniform();
    return std::sqrt(-2.0 * std::log(u)) * std::cos(2.0 * M_PI * v);
  }
  double Normal(double mean, double sigma) { return mean + sigma * Normal(); }

 private:
  static std::uint64_t Rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  static std::uint64_t SplitMix(std::uint64_t* x) {
    std::uint64_t z = (*x += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  std::uint64_t state_[4];
};

// Stream numbers of the simulator's independent random sequences.
inline constexpr std::uint64_t kStreamWorld = 1;
inline constexpr std::uint64_t kStreamSensor = 2;
inline constexpr std::uint64_t kStreamOdometry = 3;

}  // namespace freespace::sim
