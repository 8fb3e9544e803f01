#include "renderer.h"

#include <algorithm>
#include <chrono>
#include <exception>
#include <stdexcept>
#include <string>
#include <thread>

#include "kernel.h"
#include "ticks.h"
#include "tile_workers.h"

namespace sphrect::render {

Renderer::Renderer(std::shared_ptr<const RenderScene> scene, RenderOptions options)
    : scene_(std::move(scene)), options_(std::move(options)) {
    if (!scene_ || !scene_->committed()) throw std::invalid_argument("the renderer needs a committed scene");
    ValidateOptions(options_);
    CheckRenderMemory(options_, scene_->camera.width, scene_->camera.height,
                      scene_->ImageMemoryBytes());  // before the tree and the images
    if (ChoosesByLightTree(options_.light_selection)) scene_->BuildLightTree();
    threads_ = options_.threads > 0 ? options_.threads : int(std::max(1u, std::thread::hardware_concurrency()));
    view_ = MakeCameraView(*scene_, scene_->camera);
    ClearImages();
}

Renderer::~Renderer() = default;

void Renderer::ClearImages() {
    const size_t pixels = size_t(width()) * height();
    sums_.assign(options_.techniques.size(), std::vector<double>(3 * pixels, 0.0));
    counts_.assign(pixels, 0);
    alpha_sums_.assign(pixels, 0.0);
    std::lock_guard<std::mutex> s(stats_mutex_);
    stats_.assign(options_.techniques.size(), TechniqueStats{});
}

void Renderer::SetCamera(const CameraModel& camera) {
    std::unique_lock<std::mutex> lock(render_mutex_, std::try_to_lock);
    if (!lock.owns_lock()) throw std::logic_error("this Renderer is rendering: set its camera between renders");
    ValidateCamera(camera);
    CheckRenderMemory(options_, camera.width, camera.height, scene_->ImageMemoryBytes());
    CameraView view = MakeCameraView(*scene_, camera);
    std::unique_lock<std::shared_mutex> images(images_mutex_);  // no reader sees the images while they change
    view_ = std::move(view);
    ClearImages();
    next_sample_ = pass_ = 0;
}

std::vector<std::string> Renderer::Features() const {
    SceneFeatures f = scene_->features();  // the scene's, with the view's camera
    f.dof = view_.dof;
    f.orthographic = view_.camera.orthographic;
    return f.Names();
}

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
    // A Cancel() is consumed by the render it stops: the one in progress, or else the next one, which
    // then returns at once (so that a cancel from another thread just before render() is not lost).
    if (cancel_.exchange(false)) return false;
    const auto start = std::chrono::steady_clock::now();
    int passes = 0;
    bool complete = true;
    for (;;) {
        const auto pass_start = std::chrono::steady_clock::now();
        try {
            complete = RenderPass(samples, progress);
        } catch (...) {  // a worker's or the progress callback's error stopped the workers through cancel_
            cancel_.store(false);
            throw;
        }
        ++passes;
        const double pass_seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - pass_start).count();
        {
            std::lock_guard<std::mutex> s(stats_mutex_);
            for (auto& st : stats_) st.wall_time += pass_seconds;
        }
        if (!complete) {
            cancel_.store(false);  // consumed
            break;
        }
        if (time_budget <= 0) break;
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        // Stop when one more pass would more likely overshoot the budget than not.
        if (elapsed + 0.5 * elapsed / passes >= time_budget) break;
        if (exhausted()) break;
    }
    return complete;
}

bool Renderer::RenderPass(int samples, const std::function<void(int, int)>& progress) {
    const RenderScene& scene = *scene_;
    const std::vector<TileRect> tiles = CutIntoTiles(width(), height(), options_.tile_size);
    std::vector<double*> sums(sums_.size());
    for (size_t k = 0; k < sums_.size(); ++k) sums[k] = sums_[k].data();
    const KernelParams params{&scene, &view_,      &options_,      samples,           next_sample_,
                              pass_,  sums.data(), counts_.data(), alpha_sums_.data()};
    const SceneFeatures& f = scene.features();
    const bool all = options_.force_all_features;
    const TileKernel kernel = SelectTileKernel(view_.dof || all, f.glossy || all, f.medium || all);

    const uint64_t ticks0 = ReadTicks();
    const auto time0 = std::chrono::steady_clock::now();
    const TileRun run = RunTiles(kernel, params, tiles, threads_, cancel_, progress);
    // The light-sampling ticks in seconds, at the tick rate measured over this pass.
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - time0).count();
    const uint64_t ticks = ReadTicks() - ticks0;
    const double seconds_per_tick = ticks > 0 ? seconds / double(ticks) : 0.0;
    const bool complete = run.done == int(tiles.size());
    {
        std::lock_guard<std::mutex> s(stats_mutex_);
        for (size_t k = 0; k < stats_.size(); ++k) {
            TechniqueStats& st = stats_[k];
            const TechniqueTally& tt = run.tally.technique[k];
            const double light = double(tt.light_ticks) * seconds_per_tick;
            st.light_time += light;
            st.shading_time += std::max(0.0, tt.total_seconds - light);
            st.camera_time += run.tally.camera_seconds;
            st.tile_time += run.tally.tile_seconds;
            st.trace_time += tt.trace_seconds;
            st.camera_trace_time += run.tally.camera_trace_seconds;
            st.rays += tt.rays;
            st.dropped_samples += tt.dropped;
            st.camera_rays += run.tally.camera_rays;
            st.surface_hits += run.tally.surface_hits;
            if (complete) st.samples += uint64_t(samples);
        }
    }
    // Sample indices advance even for a cancelled pass, so finished tiles never reuse them.
    next_sample_ += uint32_t(samples);
    ++pass_;
    if (run.worker_error) std::rethrow_exception(run.worker_error);
    if (run.progress_error) std::rethrow_exception(run.progress_error);
    return complete;
}

void ResolveImage(const double* sums, const uint32_t* counts, const double* alpha_sums, bool film_alpha, size_t pixels,
                  float* out) {
    for (size_t i = 0; i < pixels; ++i) {
        const double inv = counts[i] > 0 ? 1.0 / counts[i] : 0.0;
        out[4 * i + 0] = float(sums[3 * i + 0] * inv);
        out[4 * i + 1] = float(sums[3 * i + 1] * inv);
        out[4 * i + 2] = float(sums[3 * i + 2] * inv);
        out[4 * i + 3] = film_alpha && counts[i] > 0 ? float(alpha_sums[i] * inv) : 1.0f;
    }
}

void Renderer::Image(int k, float* out) const {
    ResolveImage(Sums(k).data(), counts_.data(), alpha_sums_.data(), scene_->film_alpha, counts_.size(), out);
}

const std::vector<double>& Renderer::Sums(int k) const {
    if (k < 0 || size_t(k) >= sums_.size()) throw std::out_of_range("technique index out of range");
    return sums_[k];
}

void Renderer::StartAt(uint32_t first_sample, uint32_t pass) {
    std::unique_lock<std::mutex> lock(render_mutex_, std::try_to_lock);
    if (!lock.owns_lock()) throw std::logic_error("this Renderer is already rendering");
    if (next_sample_ != 0 || pass_ != 0)
        throw std::logic_error("a renderer starts at a sample range only before it renders anything");
    if (uint64_t(first_sample) * uint64_t(options_.light_samples) >= kSampleIndexLimit)
        throw std::invalid_argument("the first sample x light samples is more than a render takes");
    next_sample_ = first_sample;
    pass_ = pass;
}

TechniqueStats Renderer::Stats(int k) const {
    std::shared_lock<std::shared_mutex> images(images_mutex_);  // SetCamera resets the stats
    if (k < 0 || size_t(k) >= stats_.size()) throw std::out_of_range("technique index out of range");
    std::lock_guard<std::mutex> s(stats_mutex_);
    return stats_[k];
}

}  // namespace sphrect::render
