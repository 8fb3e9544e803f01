// Owen-scrambled Sobol' points (patterns.h) for many pixels' sample dimensions at once: the index shuffle, the second
// dimension's generator matrix (its byte tables, gathered) and both coordinates' scrambles in SIMD lanes of 32-bit
// integers, each lane with its own keys, with the instruction set chosen at run time (Google Highway).  Integer
// arithmetic throughout: every point is the scalar code's bit for bit (tests/native/test_patterns.cpp), so images do
// not change.  Batched over a chunk's pixels rather than one pixel's few points, since a vector of points waits on its
// chains of multiplications: many vectors in flight hide that.
#pragma once

#include <cstddef>
#include <cstdint>

#include "vec3.h"

namespace sphrect {

// Per point: its Sobol' index, whether it is shuffled (all bits set) or not (0) and the shuffle's seed, and the
// scramble keys of its two coordinates.
struct SobolLanes {
    const uint32_t *index, *shuffled, *shuffle_seed, *key_x, *key_y;
};

// out[i] = ScrambledSobolPoint(j, key_x[i], key_y[i]) for i < n, where j = index[i], or for a shuffled point
// OwenScramble(index[i], shuffle_seed[i]).  No allocation.
void ScrambledSobolPointsBatch(const SobolLanes& lanes, size_t n, Point2<float>* out);

}  // namespace sphrect
