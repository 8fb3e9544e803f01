// The procedural textures' float helpers against the library functions they stand in for, bit for bit: Cycles'
// hashes take floats by their bits, so a floor that lost -0 or a truncation that differed out of range would move
// patterns.  (Their values against Cycles 3.4: tests/blender/test_procedural_textures.py.)
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "render/svm/procedural_textures.h"

using namespace sphrect::render::svm;

TEST(ProceduralTextures, FloorIsFloorfBitForBit) {
    const float inf = std::numeric_limits<float>::infinity();
    const float edge[] = {0.0f,       -0.0f,       0.5f,       -0.5f,       1.0f,  -1.0f,  -1e-45f, 1e-45f,
                          8388607.5f, -8388607.5f, 8388608.0f, -8388609.0f, 3e38f, -3e38f, inf,     -inf};
    for (float x : edge) EXPECT_EQ(FloatBits(Floor(x)), FloatBits(std::floor(x))) << x;
    EXPECT_TRUE(std::isnan(Floor(std::nanf(""))));
    std::mt19937 rng(3);
    std::uniform_int_distribution<uint32_t> bits;
    for (int i = 0; i < 200000; ++i) {
        uint32_t u = bits(rng);
        float x;
        std::memcpy(&x, &u, sizeof x);
        if (std::isnan(x)) continue;
        ASSERT_EQ(FloatBits(Floor(x)), FloatBits(std::floor(x))) << x;
    }
}

TEST(ProceduralTextures, FloatToIntIsX86Truncation) {
    EXPECT_EQ(FloatToInt(2.9f), 2);
    EXPECT_EQ(FloatToInt(-2.9f), -2);
    EXPECT_EQ(FloatToInt(-2147483648.0f), INT32_MIN);
    EXPECT_EQ(FloatToInt(2147483520.0f), 2147483520);
    // cvttss2si's "integer indefinite" for what does not fit, and NaN.
    EXPECT_EQ(FloatToInt(2147483648.0f), INT32_MIN);
    EXPECT_EQ(FloatToInt(-1e20f), INT32_MIN);
    EXPECT_EQ(FloatToInt(std::nanf("")), INT32_MIN);
}

TEST(ProceduralTextures, HashesAreLookup3) {
    // hash_uint(k) is lookup3's hashword(&k, 1, 13); values from a separate Python transcription of lookup3.
    EXPECT_EQ(HashUint(0), 0x9519dc65u);
    EXPECT_EQ(HashUint(1), 0x4ad7c6a0u);
    EXPECT_EQ(HashUint(0xdeadbeefu), 0xf385ca09u);
    // Inputs differing in one word give unrelated hashes, in [0, 1] as floats.
    EXPECT_NE(HashUint3(1, 2, 3), HashUint3(1, 2, 4));
    EXPECT_NE(HashUint4(1, 2, 3, 4), HashUint4(2, 1, 3, 4));
    EXPECT_LE(UintToFloatIncl(0xFFFFFFFFu), 1.0f);
    EXPECT_EQ(UintToFloatIncl(0), 0.0f);
}
