// What a chunk's camera samples add to the image: per pixel the sum of its samples' radiance
// (non-finite samples dropped and counted), added to each technique's buffers with the count.
#pragma once

#include <cstdint>

#include "camera_stage.h"
#include "chunk.h"
#include "render/kernel.h"

namespace sphrect::render {

// sums[c] = sum of the `samples` values of chunk pixel c (values[c * samples ...]), for c < count, in
// double: samples near float's largest stay a finite mean.  Returns how many values were dropped: a NaN
// or inf sample would poison the pixel forever, so it is left out and counted (reported in the stats;
// never expected).
static inline uint64_t SumPixelSamples(const Spectrum* values, int count, uint32_t samples, Vec3d* sums) {
    uint64_t dropped = 0;
    for (int c = 0; c < count; ++c) {
        Vec3d sum;
        for (uint32_t i = 0; i < samples; ++i) {
            const Spectrum& l = values[size_t(c) * samples + i];
            if (IsFinite(l)) {
                sum += Vec3d(l.x, l.y, l.z);
            } else {
                ++dropped;
            }
        }
        sums[c] = sum;
    }
    return dropped;
}

// Adds the chunk's pixel sums (technique k's at pixel_sums[k * stride + c]) to the pass's
// buffers, and its samples to the pixels' counts.
static inline void AddChunkToImage(const KernelParams& p, const TileChunk& chunk, const Vec3d* pixel_sums, int stride,
                                   const PrimaryHit* hits) {
    const size_t techniques = p.options->techniques.size();
    const uint32_t n = uint32_t(p.samples);
    for (int c = 0; c < chunk.count; ++c) {
        const uint64_t pixel = chunk.PixelIndex(c, p.view->camera.width);
        if (p.scene->film_alpha) {
            double alpha = 0;
            for (uint32_t i = 0; i < n; ++i) alpha += hits[size_t(c) * n + i].alpha;
            p.alpha_sums[pixel] += alpha;
        }
        for (size_t k = 0; k < techniques; ++k) {
            const Vec3d& sum = pixel_sums[k * stride + c];
            double* px = p.sums[k] + 3 * pixel;
            px[0] += sum.x;
            px[1] += sum.y;
            px[2] += sum.z;
        }
        p.counts[pixel] += uint32_t(p.samples);
    }
}

}  // namespace sphrect::render
