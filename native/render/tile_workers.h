// A pass's tiles rendered in parallel: workers take the tiles in order from a shared counter,
// each with its own scratch buffers and tally, while the calling thread reports progress.
#pragma once

#include <atomic>
#include <exception>
#include <functional>
#include <vector>

#include "kernel.h"

namespace sphrect::render {

// The tiles of a width x height image, tile_size pixels square (smaller at the right and bottom
// edges), row by row.
std::vector<TileRect> CutIntoTiles(int width, int height, int tile_size);

struct TileRun {
    int done = 0;                       // tiles finished
    TileTally tally;                    // summed over the workers
    std::exception_ptr worker_error;    // the first exception a worker threw (it cancelled the run)
    std::exception_ptr progress_error;  // the exception the progress callback threw (it cancelled the run)
};

// Runs `kernel` over `tiles` on up to `threads` threads.  `cancel` stops the workers (an error
// sets it); progress(done, total), if set, is called on the calling thread whenever tiles are
// done.  Throws only when a thread cannot be started (after joining the started ones).
TileRun RunTiles(TileKernel kernel, const KernelParams& params, const std::vector<TileRect>& tiles, int threads,
                 std::atomic<bool>& cancel, const std::function<void(int, int)>& progress);

}  // namespace sphrect::render
