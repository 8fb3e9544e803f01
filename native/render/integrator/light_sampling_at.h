// Light sampling at one shading or scattering point: which area light a light sample goes to,
// and the point on it (technique K on rectangles, uniform by area on ellipses, by solid angle
// -- or by area under `area` -- on emissive triangles), with the
// solid-angle pdfs the MIS weights of the paired BSDF/phase rays need.
#pragma once

#include <optional>

#include "core/rng.h"
#include "core/technique.h"
#include "render/scene.h"

namespace sphrect::render {

// The area light a light sample goes to, picked by power (LightSelector) with the v of the light
// sample's pattern point, and the point rescaled for the point on that light (v within the
// light's interval of the CDF, u unchanged): the choice is stratified with the pattern, each
// light getting its share of a pixel's samples.  v, not u: the triangles technique already
// rescales u to pick its triangle, so each coordinate loses bits to one rescale only.  Index -1
// (pmf 0) when the scene has none.
struct ChosenLight {
    int index = -1;
    float pmf = 0;
    Point2<float> u;  // the point on the chosen light
};

static inline ChosenLight ChooseAreaLight(const LightSelector& selector, Point2<float> light_point) {
    if (selector.Empty()) return {};
    float v = 0;
    const int i = selector.SelectRemapped(light_point.v, &v);
    return {i, selector.pmf[i], {light_point.u, v}};
}

// The light choice used to take one number of the camera sample's rng; drawing it still keeps
// the numbers drawn after it (the medium's centre and distances) where they were, so that
// images with one area light stay bit-identical to those of independent choices.
static inline void SkipFormerLightChoiceNumber(const LightSelector& selector, PCG32& rng) {
    if (!selector.Empty()) rng.NextFloat();
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
        if (l.shape == AreaShape::Triangle) {
            if (K == Technique::Area) return SampleTriangleArea(l, origin_, u);
            return SampleTriangleSolidAngle(TriangleSetup(index), l, origin_, u);
        }
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
        if (l.shape == AreaShape::Triangle) {
            if (K == Technique::Area) return AreaToSolidAnglePDF(l, origin_, p);
            if (index == triangle_index_) return TriangleSolidAnglePDF(triangle_, l, origin_, p);
            return TriangleSolidAnglePDF(MakeTriangleSolidAngleSetup(l, origin_), l, origin_, p);
        }
        if (index == cached_index_) return cached_->Pdf(p);
        const LightSampler<K, float> s(origin_, normal_, l.frame);  // not kept: no sample of it here
        return s.Valid() ? s.Pdf(p) : 0.0f;
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
    Vec3f origin_, normal_;
    std::optional<LightSampler<K, float>> cached_;  // set up for rectangle light `cached_index_`
    int cached_index_ = -1;
    TriangleSolidAngleSetup triangle_;  // set up for triangle light `triangle_index_`
    int triangle_index_ = -1;
};

}  // namespace sphrect::render
