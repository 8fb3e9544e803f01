// What the shading stage reads, fixed for a tile: the scene and the options that steer it.
#pragma once

#include "render/options.h"
#include "render/scene.h"

namespace sphrect::render {

struct ShadeContext {
    const RenderScene& scene;
    MisMode mis;
    MediumSampling medium_sampling;
    LightSelection light_selection;
    int light_samples;
    bool sample_bsdf;  // BSDF/phase samples are drawn: MIS on, or a background to find
    Spectrum sky;      // what a BSDF/phase ray that escapes brings: background x transmittance to infinity
    EllipseTechnique ellipse_technique;  // how disk and ellipse lights are sampled
};

template <bool kMedium>
static inline ShadeContext MakeShadeContext(const RenderScene& scene, const RenderOptions& opt) {
    return {scene,
            opt.mis,
            opt.medium_sampling,
            opt.light_selection,
            opt.light_samples,
            opt.mis != MisMode::None || !IsBlack(scene.background),
            scene.background * SegmentTransmittance<kMedium>(scene.medium, kInf),
            opt.ellipse_technique};
}

}  // namespace sphrect::render
