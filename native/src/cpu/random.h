// Counter-based random numbers for the CPU code: a value depends only on (seed, what it is for, which item), never
// on the thread or the order in which items are processed, so multithreaded results are deterministic.
#pragma once

#include <cstdint>

namespace bounce::cpu {

// splitmix64's finaliser: a bijective 64-bit hash.
inline uint64_t mix(uint64_t x) {
  x ^= x >> 30;
  x *= 0xBF58476D1CE4E5B9ull;
  x ^= x >> 27;
  x *= 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

class Rng {
 public:
  Rng(uint64_t seed, uint64_t purpose, uint64_t item) : state_(mix(mix(seed ^ mix(purpose)) ^ item)) {}
  float next() { return static_cast<float>(next_bits() >> 8) * 0x1p-24f; }  // [0, 1)
  uint32_t next_bits() {
    state_ += 0x9E3779B97F4A7C15ull;
    return static_cast<uint32_t>(mix(state_) >> 32);
  }

 private:
  uint64_t state_;
};

}  // namespace bounce::cpu
