// What a Renderer is asked to do, and the limits of its options and of one Render() call
// (the bindings parse the names against the enums' lists and export the limits to Python).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/ellipse_technique.h"
#include "core/patterns.h"
#include "core/technique.h"
#include "light_selection.h"
#include "medium.h"  // MediumSampling
#include "mis.h"

namespace sphrect::render {

constexpr int kMaxLightSamples = 4096;
// Candidates per light sample under light_selection "ris" (each costs a tree descent, a light sample and a BSDF
// evaluation).
constexpr int kMaxRisCandidates = 1024;
// More render threads than this are refused (each is an OS thread; thousands fail to start).
constexpr int kMaxThreads = 256;
constexpr int kMaxSamplesPerCall = 1 << 20;
// One pass keeps samples x light_samples pattern points per pixel in memory.
constexpr int kMaxPatternPointsPerCallLog2 = 22;
// Sample indices (camera samples x light samples) must stay within 31 bits.
constexpr uint64_t kSampleIndexLimit = uint64_t(1) << 31;

// Every default of a render: sphrect.Renderer, the add-on and the study read them (sphrect.RENDER_DEFAULTS); the
// reasons for the choices are in docs/renderer.md, "Light selection and defaults".
struct RenderOptions {
    std::vector<Technique> techniques = {Technique::Rectangle};
    // How disk and ellipse lights are sampled (every technique's pass alike).
    EllipseTechnique ellipse_technique = EllipseTechnique::SphericalEllipse;
    int light_samples = 2;             // light samples (and BSDF samples) per camera sample
    Pattern pattern = Pattern::Sobol;  // drives pixel, lens, light and BSDF sample positions
    MisMode mis = MisMode::Power;      // light sampling vs BSDF (or phase) sampling
    MediumSampling medium_sampling = MediumSampling::Mis;
    LightSelection light_selection = LightSelection::Tree;
    // Under light_selection "ris": the candidates each light sample resamples (integrator/resampled_light_choice.h).
    int ris_candidates = 4;
    uint64_t seed = 0;
    int threads = 0;  // 0: all hardware threads
    int tile_size = 16;
    // The control variate of lights seen by the camera (integrator/light_coverage.h): the exact
    // share of each pixel that a light's image covers, instead of its camera samples' estimate.
    bool analytic_light_coverage = true;
    // With MIS, also BSDF samples at purely diffuse (Lambert) hits when the lights are sampled by
    // solid angle; off, such hits take light samples alone (integrator/shade_surface.h).
    bool bsdf_samples_on_diffuse = false;
    // Textured rectangle lights (an image on an emissive quad) sampled by their blocks' power and solid angle
    // (core/rectangle_blocks.h) under every technique but `area`; off, by the technique over the whole light.
    bool emission_blocks = true;
    // The most bytes the renderer's images may take (RenderMemoryBytes); 0: DefaultMemoryLimit().
    uint64_t memory_limit = 0;
    // Benchmarks only: run the kernel with every feature compiled in (medium, glossy, depth of
    // field) whatever the scene needs, to measure what the specialised kernels save.
    bool force_all_features = false;
    // The study's cost-model sweep only (python/sphrect/study/sweep.py): seconds of busy waiting at every surface hit
    // shaded, per technique -- a costlier shader's stand-in -- and per ray traced -- a costlier scene's; neither
    // changes an image.  Each at most kMaxAddedCost.
    double added_shading_cost = 0;
    double added_ray_cost = 0;
};

constexpr double kMaxAddedCost = 1e-3;

// Throws std::invalid_argument naming the first option out of range.
void ValidateOptions(const RenderOptions& o);

// What a renderer of `o` for a width x height image holds: per technique the RGB sums (double) and
// the image a caller copies out (RGBA float), and the sample counts.
uint64_t RenderMemoryBytes(const RenderOptions& o, int width, int height);

// Half of the machine's physical memory (the limit when RenderOptions::memory_limit is 0).
uint64_t DefaultMemoryLimit();

// Throws std::invalid_argument naming the figures if RenderMemoryBytes and the scene's `image_bytes` (its textures)
// together exceed the limit.
void CheckRenderMemory(const RenderOptions& o, int width, int height, uint64_t image_bytes = 0);

// The limit CheckRenderMemory applies: RenderOptions::memory_limit, or DefaultMemoryLimit() when that is 0.
uint64_t MemoryLimit(const RenderOptions& o);

// "1.25 GiB": how the memory checks' messages state sizes.
std::string GiBText(uint64_t bytes);

// Throws std::invalid_argument if one Render(samples) call is out of range for `o`.
void ValidateRenderCall(const RenderOptions& o, int samples);

}  // namespace sphrect::render
