// Sample patterns: range, stratification (per pattern), net property of Sobol' and Hammersley,
// star discrepancy, determinism and decorrelation between seeds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "core/patterns.h"
#include "simd_targets.h"

using namespace sphrect;

namespace {

std::vector<Point2<float>> Generate(Pattern p, uint32_t n, uint64_t seed) {
    std::vector<Point2<float>> pts(n);
    GeneratePattern(p, n, seed, pts.data());
    return pts;
}

// Every elementary interval [i/2^a, (i+1)/2^a) x [j/2^b, (j+1)/2^b) with a + b = m holds
// exactly one of the n = 2^m points.  Returns an empty string or what failed.
std::string CheckNet(const std::vector<Point2<float>>& pts, int m) {
    const uint32_t n = 1u << m;
    if (pts.size() != n) return "wrong size";
    for (int a = 0; a <= m; ++a) {
        const int b = m - a;
        std::vector<int> count(n, 0);
        for (const auto& p : pts) {
            const uint32_t i = uint32_t(std::ldexp(double(p.u), a)), j = uint32_t(std::ldexp(double(p.v), b));
            ++count[(i << b) | j];
        }
        for (uint32_t c = 0; c < n; ++c)
            if (count[c] != 1)
                return "m=" + std::to_string(m) + " a=" + std::to_string(a) + " interval " + std::to_string(c) +
                       " holds " + std::to_string(count[c]) + " points";
    }
    return {};
}

// Exact star discrepancy of a 2D point set: the sup over anchored boxes is attained at
// boxes whose upper corner coordinates are point coordinates or 1; check closed boxes
// (count too high) and open boxes (count too low).  O(n^3), fine for n <= 512.
double StarDiscrepancy(const std::vector<Point2<float>>& pts) {
    const size_t n = pts.size();
    std::vector<double> xs{1.0}, ys{1.0};
    for (const auto& p : pts) {
        xs.push_back(p.u);
        ys.push_back(p.v);
    }
    double d = 0;
    for (double a : xs)
        for (double b : ys) {
            size_t closed = 0, open = 0;
            for (const auto& p : pts) {
                closed += (p.u <= a && p.v <= b);
                open += (p.u < a && p.v < b);
            }
            d = std::max({d, double(closed) / n - a * b, a * b - double(open) / n});
        }
    return d;
}

}  // namespace

TEST(Patterns, NamesRoundTrip) {
    for (Pattern p : kAllPatterns) {
        Pattern q;
        ASSERT_TRUE(ParseEnumName(PatternName(p), kAllPatterns, PatternName, &q));
        EXPECT_EQ(p, q);
    }
    Pattern q;
    EXPECT_FALSE(ParseEnumName("halton", kAllPatterns, PatternName, &q));
    EXPECT_FALSE(ParseEnumName("", kAllPatterns, PatternName, &q));
}

TEST(Patterns, PointsInHalfOpenUnitSquare) {
    for (Pattern p : kAllPatterns)
        for (uint32_t n : {1u, 2u, 3u, 7u, 16u, 100u, 256u, 1000u, 4096u})
            for (uint64_t seed : {0ull, 1ull, 12345ull, ~0ull}) {
                for (const auto& pt : Generate(p, n, seed)) {
                    ASSERT_TRUE(pt.u >= 0.f && pt.u < 1.f) << PatternName(p) << " n=" << n << " u=" << pt.u;
                    ASSERT_TRUE(pt.v >= 0.f && pt.v < 1.f) << PatternName(p) << " n=" << n << " v=" << pt.v;
                }
            }
    // The largest indices of the Sobol' sequence too (all digits set).
    for (uint32_t index : {0xffffffffu, 0xfffffffeu, 0x80000000u}) {
        const Point2<float> pt = SobolPoint(index, 7);
        EXPECT_TRUE(pt.u >= 0.f && pt.u < 1.f && pt.v >= 0.f && pt.v < 1.f);
    }
    GeneratePattern(Pattern::Latin, 0, 1, nullptr);  // n = 0 writes nothing
}

TEST(Patterns, StratifiedHasOnePointPerStratum) {
    for (uint32_t n : {1u, 2u, 3u, 4u, 7u, 12u, 16u, 22u, 30u, 64u, 97u, 100u, 1024u, 1031u}) {
        const pattern_detail::StratifiedLayout layout(n);
        // Cells: every row as tall as its share of the cells, all cells of area 1/n, near-square.
        ASSERT_EQ(layout.wide_rows * (layout.cols + 1) + (layout.rows - layout.wide_rows) * layout.cols, n);
        ASSERT_LT(layout.wide_rows, layout.rows);
        ASSERT_LE(layout.cols + (layout.wide_rows > 0), 2 * layout.rows + 1) << "n=" << n;
        ASSERT_LE(layout.rows, layout.cols + 1) << "n=" << n;
        for (uint64_t seed : {0ull, 3ull, 99ull}) {
            std::vector<int> count(n, 0);
            for (const auto& p : Generate(Pattern::Stratified, n, seed)) {
                // The row whose y-range [before, before + row cells) / n holds p.v, then the column.
                uint32_t i = 0;
                for (; i < n; ++i) {
                    uint32_t row, col, cells, before;
                    layout.Cell(i, &row, &col, &cells, &before);
                    if (col == 0 && double(p.v) >= double(before) / n && double(p.v) < double(before + cells) / n) {
                        i += uint32_t(p.u * cells);
                        break;
                    }
                }
                ASSERT_LT(i, n) << "n=" << n << " point outside every row";
                ++count[i];
            }
            for (uint32_t c = 0; c < n; ++c) ASSERT_EQ(count[c], 1) << "n=" << n << " cell " << c;
        }
    }
    // Near-square factorisations keep their exact grid (unchanged outputs); others get rows of
    // unequal cell counts instead of a 1 x n grid.
    EXPECT_EQ(pattern_detail::StratifiedLayout(16).rows, 4u);
    EXPECT_EQ(pattern_detail::StratifiedLayout(32).rows, 4u);  // 4 x 8
    EXPECT_EQ(pattern_detail::StratifiedLayout(32).wide_rows, 0u);
    const pattern_detail::StratifiedLayout prime(97);  // 10 rows: 7 of 10 cells, 3 of 9
    EXPECT_EQ(prime.rows, 10u);
    EXPECT_EQ(prime.cols, 9u);
    EXPECT_EQ(prime.wide_rows, 7u);
}

TEST(Patterns, StratifiedIsUniformForAnyCount) {
    // Equal-area cells: the mean of many seeds' points is uniform.  Chi-square over an 8 x 8 histogram
    // of 2000 seeds x n points; 63 degrees of freedom, critical value at 1e-4: 117.
    for (uint32_t n : {7u, 22u, 97u}) {
        std::vector<double> hist(64, 0.0);
        double total = 0;
        for (uint64_t seed = 0; seed < 2000; ++seed)
            for (const auto& p : Generate(Pattern::Stratified, n, seed)) {
                hist[uint32_t(p.v * 8) * 8 + uint32_t(p.u * 8)] += 1;
                total += 1;
            }
        double chi2 = 0;
        for (double h : hist) chi2 += (h - total / 64) * (h - total / 64) / (total / 64);
        EXPECT_LT(chi2, 117.0) << "n=" << n;
    }
}

TEST(Patterns, LatinHasOnePointPerRowAndColumn) {
    for (uint32_t n : {1u, 2u, 5u, 16u, 100u, 1000u})
        for (uint64_t seed : {0ull, 1ull, 77ull}) {
            std::vector<int> rows(n, 0), cols(n, 0);
            for (const auto& p : Generate(Pattern::Latin, n, seed)) {
                ++cols[uint32_t(double(p.u) * n)];
                ++rows[uint32_t(double(p.v) * n)];
            }
            for (uint32_t i = 0; i < n; ++i) {
                ASSERT_EQ(rows[i], 1) << "n=" << n << " row " << i;
                ASSERT_EQ(cols[i], 1) << "n=" << n << " column " << i;
            }
        }
    // The column permutation depends on the seed (16! permutations: a repeat would be a bug).
    const auto a = Generate(Pattern::Latin, 16, 1), b = Generate(Pattern::Latin, 16, 2);
    std::vector<int> pa(16), pb(16);
    for (int i = 0; i < 16; ++i) {
        pa[uint32_t(a[i].v * 16)] = int(a[i].u * 16);
        pb[uint32_t(b[i].v * 16)] = int(b[i].u * 16);
    }
    EXPECT_NE(pa, pb);
}

TEST(Patterns, UnscrambledSobolIsANet) {
    for (int m = 0; m <= 12; ++m) {
        std::vector<Point2<float>> pts;
        for (uint32_t i = 0; i < (1u << m); ++i)
            pts.push_back({BitsToUnitFloat(pattern_detail::ReverseBits32(i)),
                           BitsToUnitFloat(pattern_detail::SobolDimension1(i))});
        EXPECT_EQ(CheckNet(pts, m), "");
    }
}

TEST(Patterns, ScrambledSobolAndHammersleyAreNets) {
    for (Pattern p : {Pattern::Sobol, Pattern::Hammersley})
        for (int m = 0; m <= 12; ++m)
            for (uint64_t seed : {0ull, 1ull, 2ull, 0xdeadbeefull})
                EXPECT_EQ(CheckNet(Generate(p, 1u << m, seed), m), "") << PatternName(p) << " seed " << seed;
    // The check can fail: independent points and jittered grids are not nets.
    EXPECT_NE(CheckNet(Generate(Pattern::Independent, 256, 0), 8), "");
    EXPECT_NE(CheckNet(Generate(Pattern::Stratified, 256, 0), 8), "");
}

TEST(Patterns, EveryAlignedBlockOfTheSobolSequenceIsANet) {
    // (0,2)-sequence: points [k 2^m, (k+1) 2^m) form a (0,m,2)-net, so progressive passes
    // that continue the index keep the stratification.
    for (int m : {2, 4, 6})
        for (uint32_t k : {1u, 2u, 5u, 1000u}) {
            std::vector<Point2<float>> pts;
            for (uint32_t i = 0; i < (1u << m); ++i) pts.push_back(SobolPoint((k << m) + i, 42));
            EXPECT_EQ(CheckNet(pts, m), "") << "m=" << m << " block " << k;
        }
}

TEST(Patterns, OwenScrambleIsABijectionThatPreservesPrefixes) {
    // Nested uniform scrambling maps dyadic intervals onto dyadic intervals of the same size:
    // two fractions sharing their first k digits still share their first k digits after
    // scrambling, and fractions that differ stay different.
    PCG32 rng(9);
    for (uint32_t seed : {1u, 0x12345678u})
        for (int trial = 0; trial < 4096; ++trial)
            for (int k : {1, 3, 8, 20}) {
                const uint32_t x = rng.NextU32();
                const uint32_t low = (1u << (32 - k)) - 1;
                const uint32_t y = (x & ~low) | (rng.NextU32() & low);  // same first k digits
                const uint32_t sx = pattern_detail::OwenScramble(x, seed), sy = pattern_detail::OwenScramble(y, seed);
                ASSERT_EQ((sx ^ sy) & ~low, 0u);
                if (x != y) {
                    ASSERT_NE(sx, sy);
                }
            }
}

TEST(Patterns, LowDiscrepancySetsBeatIndependentPoints) {
    // Mean star discrepancy over 6 seeds at n = 256.  Independent points have
    // E[D*] ~ 1/sqrt(n) scale (about 0.07 here); nets ~ log(n)/n; jittered grids ~ n^-3/4.
    const uint32_t n = 256;
    auto mean_d = [&](Pattern p) {
        double s = 0;
        for (uint64_t seed = 0; seed < 6; ++seed) s += StarDiscrepancy(Generate(p, n, seed));
        return s / 6;
    };
    const double independent = mean_d(Pattern::Independent);
    const double stratified = mean_d(Pattern::Stratified), latin = mean_d(Pattern::Latin);
    const double hammersley = mean_d(Pattern::Hammersley), sobol = mean_d(Pattern::Sobol);
    RecordProperty("independent", std::to_string(independent));
    EXPECT_GT(independent, 0.03);
    EXPECT_LT(sobol, 0.4 * independent);
    EXPECT_LT(hammersley, 0.4 * independent);
    EXPECT_LT(stratified, 0.6 * independent);
    EXPECT_LT(latin, independent);
    // Bounds for (0,m,2)-nets in base 2 have the form n D* <= m/3 + c with c about 2 (about
    // 4.8 at m = 8); 5/n leaves a little slack.
    EXPECT_LT(sobol, 5.0 / n);
    EXPECT_LT(hammersley, 5.0 / n);
    std::printf("mean D* (n=256): independent %.4f stratified %.4f latin %.4f hammersley %.4f sobol %.4f\n",
                independent, stratified, latin, hammersley, sobol);
}

TEST(Patterns, Deterministic) {
    for (Pattern p : kAllPatterns) {
        const auto a = Generate(p, 333, 2024), b = Generate(p, 333, 2024);
        EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0]))) << PatternName(p);
        const auto c = Generate(p, 333, 2025);
        EXPECT_NE(0, std::memcmp(a.data(), c.data(), a.size() * sizeof(a[0]))) << PatternName(p);
    }
    PCG32 r1(5, 6), r2(5, 6), r3(5, 7);
    for (int i = 0; i < 100; ++i) {
        const uint32_t x = r1.NextU32();
        EXPECT_EQ(x, r2.NextU32());
        EXPECT_NE(x, r3.NextU32());  // a 2^-32 chance per draw to coincide; fixed seeds make it deterministic
    }
}

TEST(Patterns, PointIndexIsUniformAcrossConsecutiveSeeds) {
    // Point i of the set for seeds 0..S-1 (consecutive seeds, as pixel indices are) must be
    // uniform over [0,1)^2 and independent between neighbouring seeds.  Chi-square on a 4x4 grid
    // (15 dof, threshold 56.49 = p 1e-6) and |Pearson r| < 4.89/sqrt(N) (two-sided p 1e-6):
    // with 5 patterns x 3 indices x 3 statistics, the false-failure rate is below 5e-5.
    const uint32_t n = 16, S = 4096;
    for (Pattern p : kAllPatterns)
        for (uint32_t index : {0u, 5u, 15u}) {
            std::vector<Point2<float>> at(S);
            for (uint32_t s = 0; s < S; ++s) at[s] = Generate(p, n, s)[index];
            std::vector<int> count(16, 0);
            for (const auto& q : at) ++count[uint32_t(q.u * 4) * 4 + uint32_t(q.v * 4)];
            double chi2 = 0;
            for (int c : count) chi2 += (c - S / 16.0) * (c - S / 16.0) / (S / 16.0);
            EXPECT_LT(chi2, 56.49) << PatternName(p) << " index " << index;
            for (int dim = 0; dim < 2; ++dim) {
                double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
                for (uint32_t s = 0; s + 1 < S; ++s) {
                    const double x = dim ? at[s].v : at[s].u, y = dim ? at[s + 1].v : at[s + 1].u;
                    sx += x;
                    sy += y;
                    sxx += x * x;
                    syy += y * y;
                    sxy += x * y;
                }
                const double N = S - 1;
                const double r =
                    (sxy / N - sx / N * sy / N) / std::sqrt((sxx / N - sx / N * sx / N) * (syy / N - sy / N * sy / N));
                EXPECT_LT(std::abs(r), 4.89 / std::sqrt(N)) << PatternName(p) << " index " << index << " dim " << dim;
            }
        }
}

// The chunk-wide Sobol' batch (SobolPointsBatch, core/sobol_batch.h) gives SampleDimensionPoints' points bit for bit,
// shuffled or not, for requests of every length around a vector's lanes, on every instruction set.
TEST(Patterns, SobolPointsBatchEqualsSampleDimensionPoints) {
    ForEachTarget([] {
        SobolPointsBatch batch;
        for (int round = 0; round < 3; ++round) {  // (a reused batch: cleared, its buffers kept)
            batch.Clear();
            std::vector<std::vector<Point2<float>>> got, want;
            uint64_t seed = 7 + uint64_t(round);
            for (uint32_t n = 1; n <= 37; n += 3) {
                for (bool shuffle : {false, true}) {
                    seed = MixBits(seed);
                    const uint32_t first = uint32_t(seed % 1000) * uint32_t(n % 4 + 1);
                    want.emplace_back(n);
                    SampleDimensionPoints(Pattern::Sobol, n, first, 2, seed, shuffle, want.back().data());
                    got.emplace_back(n, Point2<float>{-1, -1});
                    batch.Add(n, first, seed, shuffle, got.back().data());
                }
            }
            batch.Generate();
            for (size_t r = 0; r < want.size(); ++r)
                for (size_t i = 0; i < want[r].size(); ++i) {
                    EXPECT_EQ(std::memcmp(&got[r][i], &want[r][i], sizeof(Point2<float>)), 0)
                        << "request " << r << " point " << i;
                }
        }
    });
}
