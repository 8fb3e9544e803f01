// How a tile is cut into chunks: runs of whole pixels, row by row, of at most ~kChunkSamples
// camera samples and ~kChunkLightSamples light samples (each queues its occlusion rays).  The
// camera stage runs for the whole chunk, then each technique over it, so timers run once per
// chunk and the buffers stay small whatever the sample counts.
#pragma once

#include <algorithm>
#include <cstdint>

#include "render/kernel.h"

namespace sphrect::render {

constexpr uint64_t kChunkSamples = 1024, kChunkLightSamples = 4096;

static inline int TilePixels(const TileRect& tile) { return (tile.x1 - tile.x0) * (tile.y1 - tile.y0); }

// Pixels per chunk for `samples` camera samples per pixel with `light_samples` each (at least 1).
static inline int ChunkPixels(const TileRect& tile, uint32_t samples, uint32_t light_samples) {
    return int(std::clamp<uint64_t>(
        std::min(kChunkSamples / samples, kChunkLightSamples / (uint64_t(samples) * light_samples)), 1,
        uint64_t(TilePixels(tile))));
}

// Pixels [first, first + count) of a tile, counted row by row.
struct TileChunk {
    TileRect tile;
    int first = 0, count = 0;

    int X(int c) const { return tile.x0 + (first + c) % (tile.x1 - tile.x0); }
    int Y(int c) const { return tile.y0 + (first + c) / (tile.x1 - tile.x0); }
    // Index of chunk pixel c in an image `width` pixels wide.
    uint64_t PixelIndex(int c, int width) const { return uint64_t(Y(c)) * width + X(c); }
};

}  // namespace sphrect::render
