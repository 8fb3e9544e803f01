#include "renderer.h"

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <stdexcept>
#include <string>
#include <thread>

#include "kernel.h"
#include "ticks.h"

namespace sphrect::render {

Renderer::Renderer(std::shared_ptr<const RenderScene> scene, RenderOptions options)
    : scene_(std::move(scene)), options_(std::move(options)) {
    if (!scene_ || !scene_->committed()) throw std::invalid_argument("the renderer needs a committed scene");
    ValidateOptions(options_);
    threads_ = options_.threads > 0 ? options_.threads : int(std::max(1u, std::thread::hardware_concurrency()));
    const size_t pixels = size_t(width()) * height();
    sums_.assign(options_.techniques.size(), std::vector<double>(3 * pixels, 0.0));
    counts_.assign(pixels, 0);
    stats_.assign(options_.techniques.size(), TechniqueStats{});
}

Renderer::~Renderer() = default;

bool Renderer::Render(int samples, double time_budget, const std::function<void(int, int)>& progress) {
    ValidateRenderCall(options_, samples);
    if (!(time_budget >= 0)) throw std::invalid_argument("time_budget must be >= 0");
    std::unique_lock<std::mutex> lock(render_mutex_, std::try_to_lock);
    if (!lock.owns_lock())  // e.g. render() called from its own progress callback, or from two threads
        throw std::logic_error("this Renderer is already rendering");
    auto exhausted = [&] {
        return (uint64_t(next_sample_) + uint64_t(samples)) * uint64_t(options_.light_samples) >= kSampleIndexLimit;
    };
    if (exhausted()) throw std::invalid_argument("too many samples accumulated in this renderer");
    cancel_.store(false);
    const auto start = std::chrono::steady_clock::now();
    int passes = 0;
    bool complete = true;
    for (;;) {
        const auto pass_start = std::chrono::steady_clock::now();
        complete = RenderPass(samples, progress);
        ++passes;
        const double pass_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - pass_start).count();
        {
            std::lock_guard<std::mutex> s(stats_mutex_);
            for (auto& st : stats_) st.wall_time += pass_seconds;
        }
        if (!complete || time_budget <= 0) break;
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        // Stop when one more pass would more likely overshoot the budget than not.
        if (elapsed + 0.5 * elapsed / passes >= time_budget) break;
        if (exhausted()) break;
    }
    return complete;
}

bool Renderer::RenderPass(int samples, const std::function<void(int, int)>& progress) {
    const RenderScene& scene = *scene_;
    const int w = width(), h = height(), ts = options_.tile_size;
    std::vector<TileRect> tiles;
    for (int y = 0; y < h; y += ts)
        for (int x = 0; x < w; x += ts) tiles.push_back({x, y, std::min(x + ts, w), std::min(y + ts, h)});
    const int total = int(tiles.size());

    std::vector<double*> sums(sums_.size());
    for (size_t k = 0; k < sums_.size(); ++k) sums[k] = sums_[k].data();
    const KernelParams params{&scene, &options_, samples, next_sample_, pass_, sums.data(), counts_.data()};
    const SceneFeatures& f = scene.features();
    const bool all = options_.force_all_features;
    const TileKernel kernel = SelectTileKernel(f.dof || all, f.glossy || all, f.medium || all);

    std::atomic<int> next_tile{0};
    std::mutex mutex;
    std::condition_variable cv;
    int done = 0, finished_workers = 0;
    TileTally tally;  // summed over workers under `mutex`
    tally.technique.resize(options_.techniques.size());
    std::exception_ptr worker_error;
    const uint64_t ticks0 = ReadTicks();
    const auto time0 = std::chrono::steady_clock::now();

    auto worker = [&]() {
        ThreadScratch scratch;
        TileTally local;
        local.technique.resize(options_.techniques.size());
        try {
            for (;;) {
                if (cancel_.load(std::memory_order_relaxed)) break;
                const int i = next_tile.fetch_add(1);
                if (i >= total) break;
                kernel(params, tiles[i], scratch, local);
                std::lock_guard<std::mutex> l(mutex);
                ++done;
                if (progress) cv.notify_all();  // (without a callback, only the end wakes the caller)
            }
        } catch (...) {
            std::lock_guard<std::mutex> l(mutex);
            if (!worker_error) worker_error = std::current_exception();
            cancel_.store(true);
        }
        std::lock_guard<std::mutex> l(mutex);
        tally += local;
        ++finished_workers;
        cv.notify_all();
    };

    const int n_threads = std::max(1, std::min(threads_, total));
    std::vector<std::thread> pool;
    pool.reserve(n_threads);
    std::exception_ptr progress_error;
    try {
        for (int t = 0; t < n_threads; ++t) pool.emplace_back(worker);
    } catch (...) {
        cancel_.store(true);
        for (auto& th : pool) th.join();
        throw;
    }
    // The calling thread reports progress while the workers render.
    int reported = -1;
    for (;;) {
        int now_done, now_finished;
        {
            std::unique_lock<std::mutex> l(mutex);
            cv.wait(l, [&] { return done != reported || finished_workers == n_threads; });
            now_done = done;
            now_finished = finished_workers;
        }
        if (progress && now_done != reported && !progress_error) {
            try {
                progress(now_done, total);
            } catch (...) {
                progress_error = std::current_exception();
                cancel_.store(true);
            }
        }
        reported = now_done;
        if (now_finished == n_threads) break;
    }
    for (auto& th : pool) th.join();

    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - time0).count();
    const uint64_t ticks = ReadTicks() - ticks0;
    const double seconds_per_tick = ticks > 0 ? seconds / double(ticks) : 0.0;
    {
        std::lock_guard<std::mutex> s(stats_mutex_);
        for (size_t k = 0; k < stats_.size(); ++k) {
            TechniqueStats& st = stats_[k];
            const double light = double(tally.technique[k].light_ticks) * seconds_per_tick;
            st.light_time += light;
            st.shading_time += std::max(0.0, tally.technique[k].total_seconds - light);
            st.camera_time += tally.camera_seconds;
            st.rays += tally.technique[k].rays;
            st.dropped_samples += tally.technique[k].dropped;
            st.camera_rays += tally.camera_rays;
            if (done == total) st.samples += uint64_t(samples);
        }
    }
    // Sample indices advance even for a cancelled pass, so finished tiles never reuse them.
    next_sample_ += uint32_t(samples);
    ++pass_;
    if (worker_error) std::rethrow_exception(worker_error);
    if (progress_error) std::rethrow_exception(progress_error);
    return done == total;
}

void Renderer::Image(int k, float* out) const {
    if (k < 0 || size_t(k) >= sums_.size()) throw std::out_of_range("technique index out of range");
    const size_t pixels = counts_.size();
    const double* s = sums_[k].data();
    for (size_t i = 0; i < pixels; ++i) {
        const double inv = counts_[i] > 0 ? 1.0 / counts_[i] : 0.0;
        out[4 * i + 0] = float(s[3 * i + 0] * inv);
        out[4 * i + 1] = float(s[3 * i + 1] * inv);
        out[4 * i + 2] = float(s[3 * i + 2] * inv);
        out[4 * i + 3] = 1.0f;
    }
}

TechniqueStats Renderer::Stats(int k) const {
    if (k < 0 || size_t(k) >= stats_.size()) throw std::out_of_range("technique index out of range");
    std::lock_guard<std::mutex> s(stats_mutex_);
    return stats_[k];
}

}  // namespace sphrect::render
