// Random numbers for the sample patterns and the renderer.
//
// PCG32 is O'Neill's permuted congruential generator ("PCG: A Family of Simple
// Fast Space-Efficient Statistically Good Algorithms for Random Number
// Generation", 2014), variant XSH-RR: a 64-bit LCG whose state is output through
// a xorshift and a data-dependent rotation.  `stream` selects one of 2^63
// independent sequences (the LCG increment must be odd).
//
// MixBits is a 64-bit finalizer (xorshift-multiply, the structure of
// MurmurHash3's fmix64 with Stafford's "Mix13" constants): a bijection of
// uint64 with full avalanche, used to turn structured seeds (pixel index,
// pass number, ...) into decorrelated ones.
#pragma once

#include <cstdint>

namespace sphrect {

inline constexpr uint64_t MixBits(uint64_t v) {
    v ^= v >> 30;
    v *= 0xbf58476d1ce4e5b9ull;
    v ^= v >> 27;
    v *= 0x94d049bb133111ebull;
    v ^= v >> 31;
    return v;
}

// Largest float below 1.
inline constexpr float kOneMinusEpsilonF = 0x1.fffffep-1f;

// uint32 -> float in [0,1): the top 24 bits, exactly representable, so never 1.
inline constexpr float BitsToUnitFloat(uint32_t bits) { return float(bits >> 8) * 0x1p-24f; }

class PCG32 {
  public:
    explicit PCG32(uint64_t seed, uint64_t stream = 0) { Seed(seed, stream); }

    void Seed(uint64_t seed, uint64_t stream = 0) {
        state_ = 0;
        inc_ = (stream << 1) | 1u;
        NextU32();
        state_ += seed;
        NextU32();
    }

    uint32_t NextU32() {
        const uint64_t old = state_;
        state_ = old * kMultiplier + inc_;
        const uint32_t xorshifted = uint32_t(((old >> 18) ^ old) >> 27);
        const uint32_t rot = uint32_t(old >> 59);
        return (xorshifted >> rot) | (xorshifted << ((32 - rot) & 31));
    }

    // Uniform in [0, bound) without modulo bias (Lemire's multiply-shift with rejection).
    uint32_t NextBounded(uint32_t bound) {
        uint64_t m = uint64_t(NextU32()) * bound;
        uint32_t low = uint32_t(m);
        if (low < bound) {
            const uint32_t threshold = uint32_t(-bound) % bound;
            while (low < threshold) {
                m = uint64_t(NextU32()) * bound;
                low = uint32_t(m);
            }
        }
        return uint32_t(m >> 32);
    }

    float NextFloat() { return BitsToUnitFloat(NextU32()); }  // [0,1)

  private:
    static constexpr uint64_t kMultiplier = 0x5851f42d4c957f2dull;
    uint64_t state_ = 0, inc_ = 1;
};

}  // namespace sphrect
