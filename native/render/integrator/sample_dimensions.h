// The sample dimensions of a camera sample -- pixel jitter, lens, light samples, BSDF/phase
// samples, and a seed for its remaining random numbers -- each drawn from the pass's pattern
// with a seed of its own per pixel (core/patterns.h: SampleDimensionPoints, DimensionSeed).
#pragma once

#include <cstdint>

#include "core/patterns.h"
#include "core/rng.h"
#include "chunk.h"
#include "render/kernel.h"

namespace sphrect::render {

// Salts of the sample dimensions (DimensionSeed).
// kDimLightEdge: the grid of light_coverage.h's EstimateSeenCoverage (per pixel and pass).
enum Dimension : uint64_t { kDimPixel = 1, kDimLens = 2, kDimLight = 3, kDimBsdf = 4, kDimRng = 5, kDimLightEdge = 6 };

// The seed of pixel `pixel`'s patterns under the render's seed.
static inline uint64_t PixelSeed(uint64_t render_seed, uint64_t pixel) {
    return MixBits(MixBits(render_seed + 0x632be59bd9b4e019ull) ^ (pixel + 1));
}

// Where a pixel's pattern points go: per camera sample one pixel jitter and one lens point, and
// light_samples light and BSDF/phase points each.
struct PixelSamplePoints {
    Point2<float>* pixel;
    Point2<float>* lens;  // used when kDof
    Point2<float>* light;
    Point2<float>* bsdf;  // used when BSDF/phase samples are drawn
};

// The points of the pass's camera samples [first_sample, first_sample + samples) of one pixel.
// Light and BSDF points are numbered over (camera sample, light sample) pairs; every dimension
// but the pixel jitter draws its points in its own order, so that no two are tied together.
template <bool kDof>
static inline void FillPixelSamplePoints(const KernelParams& p, uint64_t pixel_seed, bool sample_bsdf,
                                         const PixelSamplePoints& out) {
    const Pattern pattern = p.options->pattern;
    const uint32_t n = uint32_t(p.samples), nl = uint32_t(p.options->light_samples);
    SampleDimensionPoints(pattern, n, p.first_sample, p.pass, DimensionSeed(pixel_seed, kDimPixel), false, out.pixel);
    if constexpr (kDof)
        SampleDimensionPoints(pattern, n, p.first_sample, p.pass, DimensionSeed(pixel_seed, kDimLens), true, out.lens);
    SampleDimensionPoints(pattern, n * nl, p.first_sample * nl, p.pass, DimensionSeed(pixel_seed, kDimLight), true,
                          out.light);
    if (sample_bsdf)  // BSDF/phase sample positions only when those samples are drawn
        SampleDimensionPoints(pattern, n * nl, p.first_sample * nl, p.pass, DimensionSeed(pixel_seed, kDimBsdf), true,
                              out.bsdf);
}

// The points of the pass's camera samples of every pixel of the chunk: pixel c's at pixel_points / lens_points
// [c samples ...] and light_points / bsdf_points [c samples light_samples ...] (FillPixelSamplePoints' points).  Sobol'
// draws them for all pixels in one SIMD batch (SobolPointsBatch), the other patterns pixel by pixel.
template <bool kDof>
static inline void FillChunkSamplePoints(const KernelParams& p, const TileChunk& chunk, int width, bool sample_bsdf,
                                         ThreadScratch& scratch) {
    const uint32_t n = uint32_t(p.samples), nl = uint32_t(p.options->light_samples);
    auto pixel_points = [&](int c) {
        const size_t first = size_t(c) * n, first_point = first * nl;
        return PixelSamplePoints{&scratch.pixel_points[first], &scratch.lens_points[first],
                                 &scratch.light_points[first_point], &scratch.bsdf_points[first_point]};
    };
    if (p.options->pattern != Pattern::Sobol) {
        for (int c = 0; c < chunk.count; ++c)
            FillPixelSamplePoints<kDof>(p, PixelSeed(p.options->seed, chunk.PixelIndex(c, width)), sample_bsdf,
                                        pixel_points(c));
        return;
    }
    SobolPointsBatch& batch = scratch.sobol_points;
    batch.Clear();
    for (int c = 0; c < chunk.count; ++c) {  // as FillPixelSamplePoints
        const uint64_t pixel_seed = PixelSeed(p.options->seed, chunk.PixelIndex(c, width));
        const PixelSamplePoints out = pixel_points(c);
        batch.Add(n, p.first_sample, DimensionSeed(pixel_seed, kDimPixel), false, out.pixel);
        if constexpr (kDof) batch.Add(n, p.first_sample, DimensionSeed(pixel_seed, kDimLens), true, out.lens);
        batch.Add(n * nl, p.first_sample * nl, DimensionSeed(pixel_seed, kDimLight), true, out.light);
        if (sample_bsdf) batch.Add(n * nl, p.first_sample * nl, DimensionSeed(pixel_seed, kDimBsdf), true, out.bsdf);
    }
    batch.Generate();
}

// The seed of the random numbers camera sample `sample_index` (global) of the pixel draws
// outside the pattern: light choice, medium distances.
static inline uint64_t CameraSampleRngSeed(uint64_t pixel_seed, uint32_t sample_index) {
    return MixBits(DimensionSeed(pixel_seed, kDimRng) ^ (uint64_t(sample_index) * 0xbf58476d1ce4e5b9ull));
}

}  // namespace sphrect::render
