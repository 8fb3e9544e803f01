// Light sampling at one shading or scattering point: which area light a light sample goes to,
// and the point on it (technique K on rectangles, the ellipse technique on ellipses, by solid angle
// -- or by area under `area` -- on emissive triangles), with the
// solid-angle pdfs the MIS weights of the paired BSDF/phase rays need.
#pragma once

#include <algorithm>
#include <new>
#include <type_traits>

#include "core/rng.h"
#include "core/technique.h"
#include "ellipse_sampling_at.h"
#include "render/light_selection.h"
#include "render/options.h"
#include "render/scene.h"

namespace sphrect::render {

// The emitter a light sample goes to and the point on it.  "power": an area light picked by
// power (LightSelector) with the v of the light sample's pattern point, and the point rescaled
// for the point on that light (v within the light's interval of the CDF, u unchanged): the
// choice is stratified with the pattern, each light getting its share of a pixel's samples.
// v, not u: the triangles technique already rescales u to pick its triangle, so each
// coordinate loses bits to one rescale only.  "tree": the light tree picks an area, point or
// spot light with the same v (LightTree::Sample at the receiver, v rescaled at each level and
// handed on).  index: the area light, -1 if none; delta: the point/spot light the tree chose,
// -1 if none; pmf 0 when nothing was chosen.
struct ChosenLight {
    int index = -1;
    int delta = -1;
    float pmf = 0;
    Point2<float> u;                              // the point on the chosen light
    const LightSample<float>* batched = nullptr;  // its sample, where taken for the chunk (batched_light_samples.h)
};

static inline ChosenLight ChooseLightByPower(const LightSelector& selector, Point2<float> light_point) {
    if (selector.Empty()) return {};
    float v = 0;
    const int i = selector.SelectRemapped(light_point.v, &v);
    return {i, -1, selector.pmf[i], {light_point.u, v}};
}

// `tree`: the tree at the receiver (its normal 0 in a medium: no horizon).
// The light of the tree's sample s, for the light sample with pattern point light_point (s from its v).
static inline ChosenLight ChosenFromTree(const RenderScene& scene, const LightTreeSample& s,
                                         Point2<float> light_point) {
    if (s.emitter < 0 || !(s.pmf > 0)) return {};
    const TreeEmitterRef& ref = scene.light_tree_refs()[s.emitter];
    if (ref.kind == TreeEmitterKind::Delta) return {-1, ref.index, s.pmf, {light_point.u, s.u}};
    return {ref.index, -1, s.pmf, {light_point.u, s.u}};
}

static inline ChosenLight ChooseLightFromTree(const RenderScene& scene, LightTreeAt& tree, Point2<float> light_point) {
    return ChosenFromTree(scene, tree.Sample(light_point.v), light_point);
}

// Whether light samples have an emitter to go to (otherwise only BSDF samples may be drawn).
static inline bool HasChoosableLights(const RenderScene& scene, LightSelection selection) {
    return ChoosesByLightTree(selection) ? !scene.light_tree().Empty() : !scene.light_selector.Empty();
}

// Delta lights evaluated once per camera sample (each casts its shadow ray): all of them with
// "power"; with "tree" and "ris" those beside the tree (suns, and point and spot lights while they are few).
template <class F>
static inline void ForEachDeltaLightEvaluatedOnce(const RenderScene& scene, LightSelection selection, F&& f) {
    if (selection == LightSelection::Power) {
        for (const DeltaLight& d : scene.delta_lights) f(d);
    } else {
        for (uint32_t i : scene.delta_lights_beside_tree) f(scene.delta_lights[i]);
    }
}

// Whether rectangle light l is sampled by its blocks under technique K: textured, with blocks (not a light with
// spread, sampled on its clipped part), and the option (RenderOptions::emission_blocks) on.
static inline bool SampledByBlocks(const RenderScene& scene, const AreaLight& l, Technique K, bool emission_blocks) {
    return l.texture >= 0 && K != Technique::Area && emission_blocks &&
           scene.textured_emitters[size_t(l.texture)].HasBlocks();
}

// The light choice used to take one number of the camera sample's rng; drawing it still keeps
// the numbers drawn after it (the medium's centre and distances) where they were, so that
// images with one area light stay bit-identical to those of independent choices.
static inline void SkipFormerLightChoiceNumber(const LightSelector& selector, PCG32& rng) {
    if (!selector.Empty()) rng.NextFloat();
}

// A rectangle's sampler (with spread: of the sub-rectangle SpreadClippedFrame) is set up once per (point, light) --
// lazily, by the first sample of that light or the first pdf a BSDF/phase ray needs of it -- and kept for the following
// samples and pdfs of that light: up to kKeptSamplers of them, the oldest replaced (4 light samples on the studio's 4
// softboxes set up ~2 instead of ~3.5).  No allocation: the samplers live in place.
template <Technique K>
class LightSamplingAt {
  public:
    // normal: the techniques' (the cosine technique's horizon); tree_normal: the light tree's
    // receiver normal, (0,0,0) in a medium; light_samples: how many light samples the point will
    // draw (several: the tree keeps its nodes' probabilities for them, LightTreeAt); ellipse_technique:
    // how ellipse lights are sampled; emission_blocks: textured rectangles by their blocks (RenderOptions).
    LightSamplingAt(const RenderScene& scene, LightSelection selection, const Vec3f& origin, const Vec3f& normal,
                    const Vec3f& tree_normal, int light_samples,
                    EllipseTechnique ellipse_technique = RenderOptions{}.ellipse_technique,
                    bool emission_blocks = RenderOptions{}.emission_blocks)
        : scene_(scene),
          selection_(selection),
          origin_(origin),
          normal_(normal),
          tree_(scene.light_tree(), origin, tree_normal, light_samples > 1),
          ellipse_(ellipse_technique),
          emission_blocks_(emission_blocks) {}

    // `rectangle_ltc`: the glossy lobe its samplers follow at this point (before the first sample or pdf).
    void FollowGlossyLobe(const GlossyLobe<float>& lobe) { glossy_lobe_ = lobe; }

    // The emitter of the light sample with pattern point light_point, at this receiver (under "ris": one candidate).
    ChosenLight Choose(Point2<float> light_point) {
        if (ChoosesByLightTree(selection_)) return ChooseLightFromTree(scene_, tree_, light_point);
        return ChooseLightByPower(scene_.light_selector, light_point);
    }

    LightSample<float> Sample(int index, Point2<float> u) {
        const AreaLight& l = scene_.area_lights[index];
        if (l.shape == AreaShape::Ellipse) return ellipse_.Sample(l, index, origin_, u);
        if (l.shape == AreaShape::Triangle) {
            if (K == Technique::Area) return SampleTriangleArea(l, origin_, u);
            return SampleTriangleSolidAngle(TriangleSetup(index), l, origin_, u);
        }
        if (SampledByBlocks(l)) return SampleEmissionBlocks(l, u);
        const LightSampler<K, float>& s = RectangleSampler(index);
        return s.Valid() ? s.Sample(u) : LightSample<float>{};
    }

    // Solid-angle pdf with which Sample, after Choose picked area light `index`, produces
    // point p on it: pmf(index) * pdf(p) (the tree's pmf at this receiver: area light i is tree
    // emitter i; under "ris" the pdf of its candidates, the proposal, which the MIS weights use:
    // resampled_light_choice.h).
    float PDF(int index, const Vec3f& p) {
        const float pmf = ChoosesByLightTree(selection_) ? tree_.PMF(index) : scene_.light_selector.pmf[index];
        if (!(pmf > 0)) return 0;
        return pmf * PointPDF(index, p);
    }

    // Solid-angle pdf with which soft light l (tree emitter tree_emitter, -1 for a sun) sends a light sample
    // from this point in a direction of its cone: the chance it is chosen (its tree emitter's pmf under "tree";
    // 1 for the lights evaluated once: suns, and every one under "power") times the cone's uniform pdf here,
    // at the point its light samples start from (not a BSDF ray's offset origin), as PDF() for area lights.
    float SoftLightPDF(const DeltaLight& l, int tree_emitter) {
        const float pmf = ChoosesByLightTree(selection_) && tree_emitter >= 0 ? tree_.PMF(tree_emitter) : 1.0f;
        if (!(pmf > 0)) return 0;
        const float one_minus_cos = SoftConeAt(l, origin_).one_minus_cos;
        return one_minus_cos > 0 ? pmf * UniformConePDF(one_minus_cos) : 0.0f;
    }

  private:
    float PointPDF(int index, const Vec3f& p) {
        const AreaLight& l = scene_.area_lights[index];
        if (l.shape == AreaShape::Ellipse) return ellipse_.PDF(l, index, origin_, p);
        if (l.shape == AreaShape::Triangle) {
            if (K == Technique::Area) return AreaToSolidAnglePDF(l, origin_, p);
            if (index == triangle_index_) return TriangleSolidAnglePDF(triangle_, l, origin_, p);
            return TriangleSolidAnglePDF(MakeTriangleSolidAngleSetup(l, origin_), l, origin_, p);
        }
        if (SampledByBlocks(l)) return EmissionBlocksPDF(l, p);
        const LightSampler<K, float>& s = RectangleSampler(index);
        return s.Valid() ? s.PDF(p) : 0.0f;
    }

    bool SampledByBlocks(const AreaLight& l) const { return render::SampledByBlocks(scene_, l, K, emission_blocks_); }

    // A textured rectangle light: a block by its radiance and solid angle, a point in it by the rectangle map
    // (core/rectangle_blocks.h); the blocks' table set up once per (point, light), like a rectangle's sampler.  Out
    // of line and cold, as the textured emission it goes with (textured_emission.h).
    [[gnu::noinline, gnu::cold]] LightSample<float> SampleEmissionBlocks(const AreaLight& l, Point2<float> u) {
        const RectangleBlocks b = scene_.textured_emitters[size_t(l.texture)].Blocks();
        return SampleRectangleBlocks(origin_, l.frame, b, BlocksAt(l, b), u);
    }
    [[gnu::noinline, gnu::cold]] float EmissionBlocksPDF(const AreaLight& l, const Vec3f& p) {
        const RectangleBlocks b = scene_.textured_emitters[size_t(l.texture)].Blocks();
        return RectangleBlocksPDF(origin_, l.frame, b, BlocksAt(l, b), p);
    }
    const RectangleBlocksAt& BlocksAt(const AreaLight& l, const RectangleBlocks& b) {
        if (blocks_texture_ != l.texture) {
            MakeRectangleBlocksAt(origin_, l.frame, b, blocks_at_);
            blocks_texture_ = l.texture;
        }
        return blocks_at_;
    }

    // Rectangle light `index`'s sampler at this point: a kept one, or set up in the oldest slot.
    const LightSampler<K, float>& RectangleSampler(int index) {
        const int kept = std::min(set_up_, kKeptSamplers);
        for (int k = 0; k < kept; ++k)
            if (sampler_index_[k] == index) return sampler_[k].sampler;
        const int slot = set_up_++ % kKeptSamplers;
        sampler_index_[slot] = index;
        const AreaLight& l = scene_.area_lights[index];
        // With spread, the technique samples the part of the light this point receives light from (the
        // same sub-rectangle for the samples and the pdfs of the BSDF rays that hit it).
        const RectLightFrame<float> frame = l.HasSpread() ? SpreadClippedFrame(l, origin_) : l.frame;
        if constexpr (K == Technique::RectangleLtc)
            return *new (&sampler_[slot].sampler) LightSampler<K, float>(origin_, normal_, frame, glossy_lobe_);
        return *new (&sampler_[slot].sampler) LightSampler<K, float>(origin_, normal_, frame);
    }

    // Triangle lights (every solid-angle technique): the spherical triangle, kept like a
    // rectangle's sampler for the paired BSDF ray's pdf.
    const TriangleSolidAngleSetup& TriangleSetup(int index) {
        if (index != triangle_index_) {
            triangle_ = MakeTriangleSolidAngleSetup(scene_.area_lights[index], origin_);
            triangle_index_ = index;
        }
        return triangle_;
    }

    const RenderScene& scene_;
    LightSelection selection_;
    Vec3f origin_, normal_;
    GlossyLobe<float> glossy_lobe_;  // (rectangle_ltc's; none unless FollowGlossyLobe)
    LightTreeAt tree_;               // at (origin, tree_normal)
    EllipseSamplingAt ellipse_;
    bool emission_blocks_;
    static constexpr int kKeptSamplers = 4;
    // A sampler's storage, left uninitialised until it is set up (std::optional's slots were
    // zeroed with every LightSamplingAt: docs/architecture.md, measured choices).
    union SamplerSlot {
        SamplerSlot() {}
        LightSampler<K, float> sampler;
    };
    static_assert(std::is_trivially_destructible_v<LightSampler<K, float>>, "slots are never destroyed");
    SamplerSlot sampler_[kKeptSamplers];  // for rectangle light sampler_index_[k]
    int sampler_index_[kKeptSamplers];    // (slots k < min(set_up_, kKeptSamplers) are set)
    int set_up_ = 0;                      // samplers set up at this point
    TriangleSolidAngleSetup triangle_;    // set up for triangle light `triangle_index_`
    int triangle_index_ = -1;
    RectangleBlocksAt blocks_at_;  // (uninitialised) set up for the textured rectangle of texture `blocks_texture_`
    int blocks_texture_ = -1;
};

}  // namespace sphrect::render
