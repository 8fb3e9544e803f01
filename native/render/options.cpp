#include "options.h"

#include <algorithm>
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
    if (o.threads < 0) throw std::invalid_argument("threads must be >= 0 (0: all cores)");
    if (o.tile_size < 1) throw std::invalid_argument("tile_size must be positive");
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
