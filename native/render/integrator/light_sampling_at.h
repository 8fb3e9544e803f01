// Light sampling at one shading or scattering point: which area light a light sample goes to,
// and the point on it (technique K on rectangles, uniform by area on ellipses), with the
// solid-angle pdfs the MIS weights of the paired BSDF/phase rays need.
#pragma once

#include <optional>

#include "core/rng.h"
#include "core/technique.h"
#include "render/scene.h"

namespace sphrect::render {

// The area light a light sample goes to, picked by power (LightSelector) with one number of
// `rng`; index -1 (pmf 0, no number drawn) when the scene has none.
struct ChosenLight {
    int index = -1;
    float pmf = 0;
};

static inline ChosenLight ChooseAreaLight(const LightSelector& selector, PCG32& rng) {
    if (selector.Empty()) return {};
    const int i = selector.Select(rng.NextFloat());
    return {i, selector.pmf[i]};
}

// A rectangle's sampler is set up once per (point, light) -- lazily, by the first sample of
// that light -- and kept for the following samples of the light and for the pdfs of the
// paired BSDF/phase rays.  No allocation: the sampler lives in place.
template <Technique K>
class LightSamplingAt {
  public:
    LightSamplingAt(const RenderScene& scene, const Vec3f& origin, const Vec3f& normal)
        : scene_(scene), origin_(origin), normal_(normal) {}

    LightSample<float> Sample(int index, Point2<float> u) {
        const AreaLight& l = scene_.area_lights[index];
        if (l.shape == AreaShape::Ellipse) return SampleEllipseArea(l, origin_, u);
        if (index != cached_index_) {
            cached_.emplace(origin_, normal_, l.frame);
            cached_index_ = index;
        }
        return cached_->Valid() ? cached_->Sample(u) : LightSample<float>{};
    }

    // Solid-angle pdf with which Sample, after choosing the light by power, produces point p
    // on area light `index`: pmf(index) * pdf(p).
    float PDF(int index, const Vec3f& p) {
        const float pmf = scene_.light_selector.pmf[index];
        if (!(pmf > 0)) return 0;
        return pmf * PointPDF(index, p);
    }

  private:
    float PointPDF(int index, const Vec3f& p) const {
        const AreaLight& l = scene_.area_lights[index];
        if (l.shape == AreaShape::Ellipse) return EllipseAreaPDF(l, origin_, p);
        if (index == cached_index_) return cached_->Pdf(p);
        const LightSampler<K, float> s(origin_, normal_, l.frame);  // not kept: no sample of it here
        return s.Valid() ? s.Pdf(p) : 0.0f;
    }

    const RenderScene& scene_;
    Vec3f origin_, normal_;
    std::optional<LightSampler<K, float>> cached_;  // set up for rectangle light `cached_index_`
    int cached_index_ = -1;
};

}  // namespace sphrect::render
