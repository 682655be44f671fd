#pragma once
// Deterministic random numbers of the procedural generators (bump sets, Gabor noise, the scene
// generators' terrain). GL-free.
#include <cmath>
#include <cstdint>

namespace leanfade {

// SplitMix64: a tiny, portable generator (std distributions are implementation-defined, so they
// would break determinism across standard libraries). `stream` separates the sequences of
// generators that share a seed (each generator keeps its own constant, so its output is stable).
class SplitMix64 {
  public:
    // Seed k starts at G + stream + mix((k - 1) G), G the Weyl step: seed 1 starts where it always
    // has (mix(0) = 0), and other seeds start at scattered points of the sequence, so that seeds
    // k and k + j do not replay one another's stream j steps later (as seed k G + stream would).
    SplitMix64(std::uint64_t seed, std::uint64_t stream)
        : SplitMix64(kWeylStep + stream + mix((seed - 1) * kWeylStep)) {}
    // Starts from this exact state.
    explicit SplitMix64(std::uint64_t state) : state_(state) {}
    std::uint64_t next() { return mix(state_ += kWeylStep); }
    // SplitMix64's output function, a bijection of 64-bit words with mix(0) = 0.
    static constexpr std::uint64_t mix(std::uint64_t z) {
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    static constexpr std::uint64_t kWeylStep = 0x9E3779B97F4A7C15ull;
    double uniform() { return double(next() >> 11) * (1.0 / 9007199254740992.0); }  // [0, 1)
    double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }

  private:
    std::uint64_t state_;
};

// Shortest signed offset a - b on a ring of length `period` (same units as a and b).
inline double wrapped_delta(double a, double b, double period) {
    const double d = a - b;
    return d - period * std::round(d / period);
}

}  // namespace leanfade
