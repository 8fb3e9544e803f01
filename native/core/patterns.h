// 2D sample patterns over [0,1)^2 that drive the light-sampling techniques.
//
//   GeneratePattern(pattern, n, seed, out)  // n points; different seeds give decorrelated sets
//   SobolPoint(index, seed)                 // one point of the seeded Sobol' sequence, index-wise
//   SampleDimensionPoints(pattern, n, first, pass, DimensionSeed(pixel_seed, dim), shuffle, out)
//                                           // a renderer's points of one sample dimension of a pixel
//
// Every point lies in [0,1)^2 (never 1.0).  Header-only, no allocation.
//
//  independent  PCG32 stream chosen by the seed.
//  stratified   n cells of area 1/n, one point uniformly in each.  When n = rows x cols with
//               rows <= cols <= 2 rows (rows the largest divisor of n not above sqrt(n)) the cells
//               are that grid; otherwise (n prime, 2 x 11, ...) round(sqrt(n)) rows of n / rows
//               or n / rows + 1 cells each, every row as tall as its share of the cells, so the
//               cells stay near-square instead of a 1 x n grid of slivers.
//  latin        N-rooks: x-stratum a uniformly random permutation of the y-stratum (Fisher-Yates),
//               jittered within each 1/n x 1/n cell: one point in every row and every column.
//  hammersley   (i/n, radical inverse of i) randomised so that the point set stays a (0,m,2)-net in
//               base 2 when n = 2^m: x jittered inside its own column [i/n, (i+1)/n), the radical
//               inverse Owen-scrambled (nested uniform scrambling keeps every net property).
//  sobol        the first two dimensions of Sobol' (van der Corput, and the dimension of the
//               primitive polynomial x + 1), each Owen-scrambled with its own seed by Burley's
//               hash-based nested uniform scrambling ("Practical Hash-based Owen Scrambling",
//               JCGT 2020, with the Laine-Karras style permutation).  Every prefix of 2^m points
//               is a (0,m,2)-net.
//  stratified, latin and hammersley come in random order, so that point i is not tied to one
//  stratum for every seed (which would correlate pixels, and dimensions, index by index).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <utility>
#include <vector>

#include "enum_names.h"
#include "rng.h"
#include "sobol_batch.h"
#include "vec3.h"

namespace sphrect {

enum class Pattern { Independent, Stratified, Latin, Hammersley, Sobol };

inline constexpr Pattern kAllPatterns[] = {Pattern::Independent, Pattern::Stratified, Pattern::Latin,
                                           Pattern::Hammersley, Pattern::Sobol};

inline const char* PatternName(Pattern p) {
    switch (p) {
        case Pattern::Independent: return "independent";
        case Pattern::Stratified: return "stratified";
        case Pattern::Latin: return "latin";
        case Pattern::Hammersley: return "hammersley";
        case Pattern::Sobol: return "sobol";
    }
    return "?";
}

namespace pattern_detail {

inline uint32_t ReverseBits32(uint32_t v) {
    v = ((v >> 1) & 0x55555555u) | ((v & 0x55555555u) << 1);
    v = ((v >> 2) & 0x33333333u) | ((v & 0x33333333u) << 2);
    v = ((v >> 4) & 0x0f0f0f0fu) | ((v & 0x0f0f0f0fu) << 4);
    return __builtin_bswap32(v);  // the byte and half-word swaps in one instruction
}

// Nested uniform (Owen) scrambling of a 32-bit binary fraction.  In bit-reversed order the
// most significant digit is bit 0, and each step below flips digit k by a function of the
// digits before it only (adding a key carries upwards; x ^= x * even_constant flips bit k by
// bits < k), which is exactly a nested uniform scramble.  Constants from Burley (2020).
// The scramble on digits already in bit-reversed order (most significant digit = bit 0).
inline uint32_t OwenScrambleReversed(uint32_t x, uint32_t seed) {
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
}

inline uint32_t OwenScramble(uint32_t x, uint32_t seed) {
    return ReverseBits32(OwenScrambleReversed(ReverseBits32(x), seed));
}

// Second Sobol' dimension as a 32-bit binary fraction: its generator matrix is Pascal's
// triangle mod 2, i.e. direction numbers v_{k+1} = v_k ^ (v_k >> 1) from v_0 = 1/2
// (v_k is the column for bit k of the index).
constexpr uint32_t SobolDirection1(int k) {
    uint32_t v = 1u << 31;
    for (int i = 0; i < k; ++i) v ^= v >> 1;
    return v;
}

// The matrix-vector product over GF(2) a byte of the index at a time: table[b][x] is the XOR
// of the columns of the bits set in byte b = x (4 x 256 entries, built at compile time).
// `reversed` stores the columns bit-reversed, i.e. the fraction with its most significant
// digit in bit 0, the order the Owen scramble works in.
struct SobolByteTables {
    uint32_t table[4][256];
};

constexpr SobolByteTables MakeSobolByteTables(bool reversed) {
    SobolByteTables t{};
    for (int b = 0; b < 4; ++b)
        for (int x = 0; x < 256; ++x) {
            uint32_t r = 0;
            for (int j = 0; j < 8; ++j)
                if (x & (1 << j)) {
                    uint32_t v = SobolDirection1(8 * b + j);
                    if (reversed) {
                        uint32_t w = 0;
                        for (int i = 0; i < 32; ++i) w |= ((v >> i) & 1u) << (31 - i);
                        v = w;
                    }
                    r ^= v;
                }
            t.table[b][x] = r;
        }
    return t;
}

inline constexpr SobolByteTables kSobolDimension1Tables = MakeSobolByteTables(false);
inline constexpr SobolByteTables kSobolDimension1ReversedTables = MakeSobolByteTables(true);

inline uint32_t SobolByteProduct(const SobolByteTables& t, uint32_t index) {
    return t.table[0][index & 0xffu] ^ t.table[1][(index >> 8) & 0xffu] ^ t.table[2][(index >> 16) & 0xffu] ^
           t.table[3][index >> 24];
}

inline uint32_t SobolDimension1(uint32_t index) { return SobolByteProduct(kSobolDimension1Tables, index); }

// A float in [index/count, (index+1)/count), at position rand32 / 2^32 inside that interval,
// truncated to 24 bits (so < 1, and on the interval's side of every dyadic boundary that a
// float can represent: jittered strata stay in their strata).
inline float JitterInStratum(uint32_t index, uint32_t count, uint32_t rand32) {
    const uint64_t q = ((uint64_t(index) << 32) | rand32) / count;  // floor((index + r) / count * 2^32)
    return BitsToUnitFloat(uint32_t(q));
}

// Rows of the near-square grid used by `stratified`: the largest divisor of n that is <= sqrt(n).
inline uint32_t StratifiedRows(uint32_t n) {
    uint32_t r = uint32_t(std::sqrt(double(n)));
    while (r > 1 && n % r != 0) --r;
    return r < 1 ? 1 : r;
}

// The cells of `stratified`: `rows` rows, the first `wide_rows` of them with `cols` + 1 cells, the
// others with `cols`; row r spans y in [first cell of the row, first cell of the next row) / n.
struct StratifiedLayout {
    uint32_t rows, cols, wide_rows;

    explicit StratifiedLayout(uint32_t n) {
        rows = StratifiedRows(n);
        if (uint64_t(n / rows) > 2ull * rows) rows = std::max(1u, uint32_t(std::lround(std::sqrt(double(n)))));
        cols = n / rows;
        wide_rows = n % rows;
    }
    // Row, column, cells in that row, and cells before the row, of cell i (row by row).
    void Cell(uint32_t i, uint32_t* row, uint32_t* col, uint32_t* row_cells, uint32_t* before) const {
        const uint32_t wide_cells = wide_rows * (cols + 1);
        if (i < wide_cells) {
            *row = i / (cols + 1);
            *col = i % (cols + 1);
            *row_cells = cols + 1;
            *before = *row * (cols + 1);
        } else {
            *row = wide_rows + (i - wide_cells) / cols;
            *col = (i - wide_cells) % cols;
            *row_cells = cols;
            *before = wide_cells + (*row - wide_rows) * cols;
        }
    }
};

// Per-pattern sub-seeds, so x and y (and different patterns) never share randomness.
inline uint32_t SubSeed(uint64_t seed, uint64_t salt) {
    return uint32_t(MixBits(MixBits(seed) ^ (salt * 0x9e3779b97f4a7c15ull)) >> 32);
}

// Fisher-Yates: swap(i - 1, j) for i = n .. 2, j uniform in [0, i).
template <class Swap>
inline void FisherYates(uint32_t n, PCG32& rng, Swap swap) {
    for (uint32_t i = n; i > 1; --i) swap(i - 1, rng.NextBounded(i));
}

// Random order: without it, point i of `stratified`, `latin` and `hammersley` would sit in
// the same stratum for every seed, correlating pixels (and dimensions) index-wise.
inline void ShufflePoints(Point2<float>* p, uint32_t n, PCG32& rng) {
    FisherYates(n, rng, [p](uint32_t a, uint32_t b) { std::swap(p[a], p[b]); });
}

// Point `index` of Sobol' (first two dimensions), each Owen-scrambled with its own key.
// The first dimension is the radical inverse of the index, whose bit-reversed digits are the
// index itself; the second comes from the bit-reversed table: one reversal per coordinate.
inline Point2<float> ScrambledSobolPoint(uint32_t index, uint32_t key_x, uint32_t key_y) {
    const uint32_t x = ReverseBits32(OwenScrambleReversed(index, key_x));
    const uint32_t y =
        ReverseBits32(OwenScrambleReversed(SobolByteProduct(kSobolDimension1ReversedTables, index), key_y));
    return {BitsToUnitFloat(x), BitsToUnitFloat(y)};
}

// The two scramble keys of the sequence selected by `seed` (what SobolPoint uses).
struct SobolKeys {
    uint32_t x, y;
};

inline SobolKeys MakeSobolKeys(uint64_t seed) { return {SubSeed(seed, 1), SubSeed(seed, 2)}; }

}  // namespace pattern_detail

// Point `index` of the Owen-scrambled Sobol' sequence selected by `seed`.  Continuing the
// index over progressive passes continues the same sequence (prefixes of 2^m points are nets).
inline Point2<float> SobolPoint(uint32_t index, uint64_t seed) {
    using namespace pattern_detail;
    const SobolKeys k = MakeSobolKeys(seed);
    return ScrambledSobolPoint(index, k.x, k.y);
}

// Writes n points of the pattern into out[0..n).
inline void GeneratePattern(Pattern pattern, uint32_t n, uint64_t seed, Point2<float>* out) {
    using namespace pattern_detail;
    switch (pattern) {
        case Pattern::Independent: {
            PCG32 rng(MixBits(seed), MixBits(seed ^ 0x243f6a8885a308d3ull));
            for (uint32_t i = 0; i < n; ++i) {
                const float u = rng.NextFloat();
                out[i] = {u, rng.NextFloat()};
            }
            return;
        }
        case Pattern::Stratified: {
            if (n == 0) return;
            const StratifiedLayout layout(n);
            PCG32 rng(MixBits(seed), MixBits(seed ^ 0x13198a2e03707344ull));
            for (uint32_t i = 0; i < n; ++i) {
                const uint32_t rx = rng.NextU32(), ry = rng.NextU32();
                uint32_t row, col, row_cells, before;
                layout.Cell(i, &row, &col, &row_cells, &before);
                // y = (before + row_cells * ry / 2^32) / n, in 2^-32 steps (< n 2^32 < 2^64: no overflow);
                // for a full grid exactly JitterInStratum(row, rows, ry).
                const uint64_t y_bits = ((uint64_t(before) << 32) + uint64_t(row_cells) * ry) / n;
                out[i] = {JitterInStratum(col, row_cells, rx), BitsToUnitFloat(uint32_t(y_bits))};
            }
            ShufflePoints(out, n, rng);
            return;
        }
        case Pattern::Latin: {
            // Fisher-Yates shuffle of the column indices, kept as raw bits in out[].u
            // (no allocation), then each (column, row) cell gets a jittered point.
            PCG32 rng(MixBits(seed), MixBits(seed ^ 0xa4093822299f31d0ull));
            for (uint32_t i = 0; i < n; ++i) std::memcpy(&out[i].u, &i, sizeof(uint32_t));
            FisherYates(n, rng, [out](uint32_t i, uint32_t j) {
                uint32_t a, b;  // swapped as integers: the bits are not meaningful floats
                std::memcpy(&a, &out[i].u, sizeof a);
                std::memcpy(&b, &out[j].u, sizeof b);
                std::memcpy(&out[i].u, &b, sizeof b);
                std::memcpy(&out[j].u, &a, sizeof a);
            });
            for (uint32_t i = 0; i < n; ++i) {
                uint32_t col;
                std::memcpy(&col, &out[i].u, sizeof(uint32_t));
                const uint32_t rx = rng.NextU32(), ry = rng.NextU32();
                out[i] = {JitterInStratum(col, n, rx), JitterInStratum(i, n, ry)};
            }
            ShufflePoints(out, n, rng);  // rows were in order
            return;
        }
        case Pattern::Hammersley: {
            PCG32 rng(MixBits(seed), MixBits(seed ^ 0x082efa98ec4e6c89ull));
            const uint32_t scramble = SubSeed(seed, 3);
            for (uint32_t i = 0; i < n; ++i)
                out[i] = {JitterInStratum(i, n, rng.NextU32()),
                          BitsToUnitFloat(ReverseBits32(OwenScrambleReversed(i, scramble)))};
            ShufflePoints(out, n, rng);
            return;
        }
        case Pattern::Sobol: {
            const SobolKeys k = MakeSobolKeys(seed);  // as SobolPoint
            for (uint32_t i = 0; i < n; ++i) out[i] = ScrambledSobolPoint(i, k.x, k.y);
            return;
        }
    }
}

// The seed of one sample dimension (pixel position, lens, light, BSDF, ...) of the pixel whose
// seed is `pixel_seed`; `dimension` is the dimension's salt.  Each dimension gets its own
// pattern, so no two dimensions share randomness.
inline uint64_t DimensionSeed(uint64_t pixel_seed, uint64_t dimension) {
    return MixBits(pixel_seed ^ (dimension * 0x9e3779b97f4a7c15ull));
}

namespace pattern_detail {
// The seed of a dimension's shuffle (SampleDimensionPoints).
inline uint32_t ShuffleSeed(uint64_t seed) { return uint32_t(MixBits(seed ^ 0x2545f4914f6cdd1dull) >> 32); }
}  // namespace pattern_detail

// The points of one sample dimension for the global sample indices first .. first + n - 1 of a
// pixel (seed: DimensionSeed).  Sobol' continues one sequence across passes (index-wise); the
// other patterns draw a fresh set per pass.
//
// Every dimension draws its points in its own random order: with the same order, point i of the
// light pattern would be tied to point i of the pixel pattern (same stratum, or for Sobol' the
// same digits of i), correlating where in the pixel a sample lands with where on the light it
// goes -- unbiased, but skewed and much noisier.  Sobol' indices are shuffled by a nested uniform
// scramble of the index (Burley 2020, "Practical Hash-based Owen Scrambling", sec. 4): bit k of
// the index flips by a hash of the bits above it, so each aligned block of 2^m indices maps onto
// an aligned block, a (0,m,2)-net again.  The other patterns are permuted with Fisher-Yates.  One
// dimension (the pixel's) can keep its order: `shuffle` false.
inline void SampleDimensionPoints(Pattern pattern, uint32_t n, uint32_t first, uint32_t pass, uint64_t seed,
                                  bool shuffle, Point2<float>* out) {
    using namespace pattern_detail;
    const uint32_t shuffle_seed = ShuffleSeed(seed);
    if (pattern == Pattern::Sobol) {
        // SobolPoint(index, seed) point by point, with the scramble keys derived once (many pixels' points at once:
        // SobolPointsBatch).
        const SobolKeys keys = MakeSobolKeys(seed);
        if (shuffle) {
            for (uint32_t i = 0; i < n; ++i)
                out[i] = ScrambledSobolPoint(OwenScramble(first + i, shuffle_seed), keys.x, keys.y);
        } else {
            for (uint32_t i = 0; i < n; ++i) out[i] = ScrambledSobolPoint(first + i, keys.x, keys.y);
        }
        return;
    }
    const uint64_t pass_seed = MixBits(seed ^ (uint64_t(pass) * 0xd1b54a32d192ed03ull));
    GeneratePattern(pattern, n, pass_seed, out);
    if (!shuffle) return;
    PCG32 rng(MixBits(pass_seed ^ shuffle_seed), 0x9e3779b9ull);
    ShufflePoints(out, n, rng);
}

// Sobol' sample dimensions of many pixels at once: Add(n, first, seed, shuffle, out) stands for
// SampleDimensionPoints(Pattern::Sobol, n, first, pass, seed, shuffle, out) (Sobol' ignores the pass), whose points
// Generate() writes, bit for bit the same, in SIMD batches (sobol_batch.h).  Its buffers are kept: no allocation once
// they fit.
class SobolPointsBatch {
  public:
    void Clear() {
        size_ = 0;
        outs_.clear();
    }
    void Add(uint32_t n, uint32_t first, uint64_t seed, bool shuffle, Point2<float>* out) {
        using namespace pattern_detail;
        const SobolKeys keys = MakeSobolKeys(seed);
        const size_t at = size_;
        size_ += n;
        if (index_.size() < size_) {  // (grown, then kept)
            for (auto* v : {&index_, &shuffled_, &shuffle_seed_, &key_x_, &key_y_}) v->resize(2 * size_);
        }
        for (uint32_t i = 0; i < n; ++i) index_[at + i] = first + i;
        std::fill_n(&shuffled_[at], n, shuffle ? ~0u : 0u);
        std::fill_n(&shuffle_seed_[at], n, ShuffleSeed(seed));
        std::fill_n(&key_x_[at], n, keys.x);
        std::fill_n(&key_y_[at], n, keys.y);
        outs_.push_back({out, n});
    }
    void Generate() {
        points_.resize(size_);
        ScrambledSobolPointsBatch({index_.data(), shuffled_.data(), shuffle_seed_.data(), key_x_.data(), key_y_.data()},
                                  size_, points_.data());
        size_t next = 0;
        for (const auto& [out, n] : outs_) {
            std::copy(points_.begin() + ptrdiff_t(next), points_.begin() + ptrdiff_t(next + n), out);
            next += n;
        }
    }

  private:
    size_t size_ = 0;  // points added (the vectors hold at least as many)
    std::vector<uint32_t> index_, shuffled_, shuffle_seed_, key_x_, key_y_;
    std::vector<Point2<float>> points_;
    std::vector<std::pair<Point2<float>*, uint32_t>> outs_;
};

}  // namespace sphrect
