#include "options.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace sphrect::render {

void ValidateOptions(const RenderOptions& o) {
    if (o.techniques.empty()) throw std::invalid_argument("at least one technique is needed");
    for (size_t i = 0; i < o.techniques.size(); ++i)
        for (size_t j = 0; j < i; ++j)
            if (o.techniques[j] == o.techniques[i])
                throw std::invalid_argument("technique '" + std::string(TechniqueName(o.techniques[i])) +
                                            "' listed twice");
    if (std::find(kAllEllipseTechniques.begin(), kAllEllipseTechniques.end(), o.ellipse_technique) ==
        kAllEllipseTechniques.end())
        throw std::invalid_argument("ellipse_technique must be one of the EllipseTechnique values");
    if (o.light_samples < 1 || o.light_samples > kMaxLightSamples)
        throw std::invalid_argument("light_samples must be in 1.." + std::to_string(kMaxLightSamples));
    if (o.ris_candidates < 1 || o.ris_candidates > kMaxRisCandidates)
        throw std::invalid_argument("ris_candidates must be in 1.." + std::to_string(kMaxRisCandidates));
    if (o.threads < 0) throw std::invalid_argument("threads must be >= 0 (0: all cores)");
    if (o.threads > kMaxThreads)
        throw std::invalid_argument("threads must be at most " + std::to_string(kMaxThreads) + " (got " +
                                    std::to_string(o.threads) + "; 0: all cores)");
    if (o.tile_size < 1) throw std::invalid_argument("tile_size must be positive");
    for (const auto& [name, value] :
         {std::pair{"added_shading_cost", o.added_shading_cost}, std::pair{"added_ray_cost", o.added_ray_cost}})
        if (!(value >= 0 && value <= kMaxAddedCost))
            throw std::invalid_argument(std::string(name) + " must be in [0, " + std::to_string(kMaxAddedCost) +
                                        "] seconds");
}

uint64_t RenderMemoryBytes(const RenderOptions& o, int width, int height) {
    const uint64_t pixels = uint64_t(std::max(width, 0)) * uint64_t(std::max(height, 0));
    const uint64_t per_technique = pixels * (3 * sizeof(double) + 4 * sizeof(float));
    return per_technique * o.techniques.size() + pixels * (sizeof(uint32_t) + sizeof(double));  // counts, alpha
}

uint64_t DefaultMemoryLimit() {
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
    if (pages <= 0 || page <= 0) return uint64_t(8) << 30;  // unknown: 8 GiB
    return uint64_t(pages) * uint64_t(page) / 2;
}

uint64_t MemoryLimit(const RenderOptions& o) { return o.memory_limit > 0 ? o.memory_limit : DefaultMemoryLimit(); }

std::string GiBText(uint64_t bytes) {
    char text[32];
    std::snprintf(text, sizeof text, "%.2f GiB", double(bytes) / double(uint64_t(1) << 30));
    return text;
}

void CheckRenderMemory(const RenderOptions& o, int width, int height, uint64_t image_bytes) {
    const uint64_t film = RenderMemoryBytes(o, width, height), limit = MemoryLimit(o);
    if (film <= limit && image_bytes <= limit - film) return;
    throw std::invalid_argument("a " + std::to_string(width) + "x" + std::to_string(height) + " image with " +
                                std::to_string(o.techniques.size()) + " technique(s) needs " + GiBText(film) +
                                (image_bytes ? " and the scene's textures " + GiBText(image_bytes) : "") + "," +
                                " more than the memory limit of " + GiBText(limit) +
                                (o.memory_limit > 0 ? "" : " (half the physical memory)") +
                                ": lower the resolution or the techniques, or raise memory_limit");
}

void ValidateRenderCall(const RenderOptions& o, int samples) {
    if (samples < 1 || samples > kMaxSamplesPerCall)
        throw std::invalid_argument("samples must be in 1.." + std::to_string(kMaxSamplesPerCall));
    if (uint64_t(samples) * uint64_t(o.light_samples) > (uint64_t(1) << kMaxPatternPointsPerCallLog2))
        throw std::invalid_argument("samples x light_samples must be at most 2^" +
                                    std::to_string(kMaxPatternPointsPerCallLog2) +
                                    " per render() call (render in several calls, or use time_budget)");
}

}  // namespace sphrect::render
