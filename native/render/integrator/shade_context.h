// What the shading stage reads, fixed for a tile: the scene and the options that steer it.
#pragma once

#include "render/options.h"
#include "render/scene.h"
#include "render/ticks.h"

namespace sphrect::render {

struct ShadeContext {
    const RenderScene& scene;
    MisMode mis;
    MediumSampling medium_sampling;
    LightSelection light_selection;
    int light_samples;
    int ris_candidates;  // RenderOptions::ris_candidates (read under light_selection "ris")
    bool sample_bsdf;    // BSDF/phase samples are drawn: MIS on, or a background to find
    Spectrum sky;        // what a BSDF/phase ray that escapes brings: background x transmittance to infinity
    EllipseTechnique ellipse_technique;  // how disk and ellipse lights are sampled
    // Purely diffuse hits may take light samples alone (shade_surface.h, LightSamplesAlone): MIS on,
    // not RenderOptions::bsdf_samples_on_diffuse, no Light Path program (RenderScene::light_path_programs: an emitter
    // may send its BSDF rays other light than its light samples, Cycles' estimate weighs both), no ellipse light
    // sampled by area, and the choice among the lights made knowing the point: the tree's (or its resampled
    // candidates', `ris`), or one area light to choose.  By power a near, weak light is chosen far below its share of
    // the point's light, and an emissive mesh puts many small emitters on or beside other geometry, where even the
    // tree's bounds do: there only the BSDF sample's MIS weight keeps such a light sample from being a firefly
    // (docs/renderer.md, "MIS at diffuse hits").
    bool diffuse_light_samples_alone;
    // The image world where it can light anything (null: none, all black, or nothing of it crosses the medium):
    // sampled once per light sample, and found by BSDF/phase rays that escape (MIS).  environment_transmittance:
    // the medium's transmittance to infinity.
    const EnvironmentLight* environment;
    Spectrum environment_transmittance;
    bool emission_blocks;          // RenderOptions::emission_blocks
    uint64_t added_shading_ticks;  // RenderOptions::added_shading_cost in ReadTicks() units (0: none)
    uint64_t added_ray_ticks;      // RenderOptions::added_ray_cost likewise
};

template <bool kMedium>
static inline ShadeContext MakeShadeContext(const RenderScene& scene, const RenderOptions& opt) {
    return {scene,
            opt.mis,
            opt.medium_sampling,
            opt.light_selection,
            opt.light_samples,
            opt.ris_candidates,
            opt.mis != MisMode::None || !IsBlack(scene.background),
            scene.background * SegmentTransmittance<kMedium>(scene.medium, kInf),
            opt.ellipse_technique,
            opt.mis != MisMode::None && !opt.bsdf_samples_on_diffuse && !scene.light_path_programs &&
                !(opt.ellipse_technique == EllipseTechnique::Area && scene.features().ellipse_lights) &&
                (ChoosesByLightTree(opt.light_selection) || scene.area_lights.size() <= 1) &&
                !scene.features().emissive_meshes,
            scene.has_environment && !scene.environment.distribution.Empty() &&
                    !IsBlack(SegmentTransmittance<kMedium>(scene.medium, kInf))
                ? &scene.environment
                : nullptr,
            SegmentTransmittance<kMedium>(scene.medium, kInf),
            opt.emission_blocks,
            SecondsToTicks(opt.added_shading_cost),
            SecondsToTicks(opt.added_ray_cost)};
}

// The same context without MIS: light samples alone, and BSDF samples only to find the background.
static inline ShadeContext WithoutMis(const ShadeContext& c) {
    ShadeContext out = c;
    out.mis = MisMode::None;
    out.sample_bsdf = !IsBlack(c.sky);
    return out;
}

}  // namespace sphrect::render
