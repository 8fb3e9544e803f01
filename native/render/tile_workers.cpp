#include "tile_workers.h"

#include <algorithm>
#include <condition_variable>
#include <mutex>
#include <thread>

namespace sphrect::render {

std::vector<TileRect> CutIntoTiles(int width, int height, int tile_size) {
    std::vector<TileRect> tiles;
    for (int y = 0; y < height; y += tile_size)
        for (int x = 0; x < width; x += tile_size)
            tiles.push_back({x, y, std::min(x + tile_size, width), std::min(y + tile_size, height)});
    return tiles;
}

TileRun RunTiles(TileKernel kernel, const KernelParams& params, const std::vector<TileRect>& tiles, int threads,
                 std::atomic<bool>& cancel, const std::function<void(int, int)>& progress) {
    const int total = int(tiles.size());
    const size_t techniques = params.options->techniques.size();
    std::atomic<int> next_tile{0};
    std::mutex mutex;
    std::condition_variable cv;
    int finished_workers = 0;
    TileRun run;  // done, tally and worker_error under `mutex`
    run.tally.technique.resize(techniques);

    auto worker = [&]() {
        ThreadScratch scratch;
        TileTally local;
        local.technique.resize(techniques);
        try {
            for (;;) {
                if (cancel.load(std::memory_order_relaxed)) break;
                const int i = next_tile.fetch_add(1);
                if (i >= total) break;
                kernel(params, tiles[i], scratch, local);
                std::lock_guard<std::mutex> l(mutex);
                ++run.done;
                if (progress) cv.notify_all();  // (without a callback, only the end wakes the caller)
            }
        } catch (...) {
            std::lock_guard<std::mutex> l(mutex);
            if (!run.worker_error) run.worker_error = std::current_exception();
            cancel.store(true);
        }
        std::lock_guard<std::mutex> l(mutex);
        run.tally += local;
        ++finished_workers;
        cv.notify_all();
    };

    const int n_threads = std::max(1, std::min(threads, total));
    std::vector<std::thread> pool;
    pool.reserve(n_threads);
    try {
        for (int t = 0; t < n_threads; ++t) pool.emplace_back(worker);
    } catch (...) {
        cancel.store(true);
        for (auto& th : pool) th.join();
        throw;
    }
    // The calling thread reports progress while the workers render.
    int reported = -1;
    for (;;) {
        int now_done, now_finished;
        {
            std::unique_lock<std::mutex> l(mutex);
            cv.wait(l, [&] { return run.done != reported || finished_workers == n_threads; });
            now_done = run.done;
            now_finished = finished_workers;
        }
        if (progress && now_done != reported && !run.progress_error) {
            try {
                progress(now_done, total);
            } catch (...) {
                run.progress_error = std::current_exception();
                cancel.store(true);
            }
        }
        reported = now_done;
        if (now_finished == n_threads) break;
    }
    for (auto& th : pool) th.join();
    return run;
}

}  // namespace sphrect::render
