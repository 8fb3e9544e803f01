// The direct-lighting renderer: progressive, tile-parallel, several light-sampling techniques
// sharing camera rays and first hits, each with its own accumulation buffer and timings.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <shared_mutex>
#include <string>
#include <vector>

#include "camera_view.h"
#include "options.h"
#include "scene.h"

namespace sphrect::render {

struct TechniqueStats {
    uint64_t samples = 0;          // camera samples per pixel accumulated (pixels of cancelled tiles may have fewer)
    double wall_time = 0;          // seconds of Render() calls (shared by all techniques of the renderer)
    double light_time = 0;         // thread-seconds in this technique's light sampling (setup, Sample, PDF)
    double shading_time = 0;       // thread-seconds in the rest of its direct lighting: BSDF, MIS, shadow rays
    double camera_time = 0;        // thread-seconds of camera rays and first hits (shared)
    double tile_time = 0;          // thread-seconds in the tiles, whole: all stages and techniques (shared)
    double trace_time = 0;         // thread-seconds tracing this technique's rays (within shading_time): the occlusion
                                   // stream and emissive meshes' search by BSDF rays
    double camera_trace_time = 0;  // thread-seconds tracing the camera rays (within camera_time; shared)
    uint64_t rays = 0;             // shadow and BSDF/phase rays cast for this technique
    uint64_t camera_rays = 0;      // camera rays (shared)
    uint64_t surface_hits = 0;     // camera rays that hit a surface (shared)
    uint64_t dropped_samples = 0;  // non-finite camera samples left out of the image (expected 0)
};

// RGBA float32 [pixels][4] from accumulation buffers: the mean of each pixel's samples (black where
// none), alpha the film's when film_alpha, else 1.
void ResolveImage(const double* sums, const uint32_t* counts, const double* alpha_sums, bool film_alpha, size_t pixels,
                  float* out);

class Renderer {
  public:
    // Throws std::invalid_argument on bad options, an uncommitted scene, or images that would take
    // more than the memory limit (CheckRenderMemory).
    Renderer(std::shared_ptr<const RenderScene> scene, RenderOptions options);
    ~Renderer();

    // Adds `samples` camera samples per pixel; with time_budget > 0, keeps adding passes of
    // `samples` while the budget lasts (at least one pass).  `progress(done_tiles, total_tiles)`
    // is called on the calling thread.  Returns false when cancelled (partial image kept).
    // Throws std::logic_error if this renderer is already rendering (one Render() at a time).
    bool Render(int samples, double time_budget = 0, const std::function<void(int, int)>& progress = nullptr);
    // Makes this renderer render a sample range of a longer render: its next Render() call renders
    // camera samples [first_sample, first_sample + samples) as pass `pass` of that render, exactly as
    // the longer render's own pass `pass` does (the patterns depend on the sample indices and the pass
    // number, nothing else).  Only before anything is rendered (std::logic_error otherwise);
    // std::invalid_argument when first_sample x light_samples reaches kSampleIndexLimit.
    void StartAt(uint32_t first_sample, uint32_t pass);
    // Stops the render in progress at its next tile, or, when none is, the next Render() call
    // before it renders anything (each cancel stops one render).
    void Cancel() { cancel_.store(true); }
    // Renders from now on from `camera` (the scene's own at first), with the same scene: the images start
    // again, empty, at the camera's resolution, as in a new Renderer (sample indices, passes and stats too),
    // without the scene's build.  Throws std::invalid_argument for a camera the scene could not take or images
    // over the memory limit (nothing changed then), std::logic_error while rendering.
    void SetCamera(const CameraModel& camera);

    int width() const { return view_.camera.width; }
    int height() const { return view_.camera.height; }
    const RenderOptions& options() const { return options_; }
    std::vector<std::string> Features() const;  // the scene's features, with the view's camera (dof, orthographic)
    // RGBA float32 [height][width][4], row 0 at the top; mean of the samples so far.
    void Image(int technique_index, float* out) const;
    TechniqueStats Stats(int technique_index) const;
    // The accumulation buffers the image is the mean of (ResolveImage): adding two renderers' buffers
    // merges disjoint sample ranges of one render.
    const std::vector<double>& Sums(int technique_index) const;  // RGB per pixel
    const std::vector<uint32_t>& Counts() const { return counts_; }
    const std::vector<double>& AlphaSums() const { return alpha_sums_; }
    // SetCamera reallocates the images: a reader on another thread holds this while it reads the resolution, an
    // image or a buffer (the bindings do, for every reader), and SetCamera waits for it.
    std::shared_lock<std::shared_mutex> ReadLock() const { return std::shared_lock<std::shared_mutex>(images_mutex_); }
    bool FilmAlpha() const { return scene_->film_alpha; }

  private:
    bool RenderPass(int samples, const std::function<void(int, int)>& progress);

    void ClearImages();  // sized for the view's resolution

    std::shared_ptr<const RenderScene> scene_;
    RenderOptions options_;
    CameraView view_;
    int threads_ = 1;
    std::vector<std::vector<double>> sums_;  // per technique, RGB per pixel
    std::vector<uint32_t> counts_;           // camera samples per pixel
    std::vector<double> alpha_sums_;         // the film's alpha summed per pixel
    std::vector<TechniqueStats> stats_;
    uint32_t next_sample_ = 0, pass_ = 0;
    std::atomic<bool> cancel_{false};
    std::mutex render_mutex_;  // one Render() at a time
    mutable std::mutex stats_mutex_;
    mutable std::shared_mutex images_mutex_;  // the view and the buffers sized by it (ReadLock, SetCamera)
};

}  // namespace sphrect::render
