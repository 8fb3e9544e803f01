// Light sampling at one shading or scattering point: which area light a light sample goes to,
// and the point on it (technique K on rectangles, uniform by area on ellipses, by solid angle
// -- or by area under `area` -- on emissive triangles), with the
// solid-angle pdfs the MIS weights of the paired BSDF/phase rays need.
#pragma once

#include <optional>

#include "core/rng.h"
#include "core/technique.h"
#include "render/light_selection.h"
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
    Point2<float> u;  // the point on the chosen light
};

static inline ChosenLight ChooseLightByPower(const LightSelector& selector, Point2<float> light_point) {
    if (selector.Empty()) return {};
    float v = 0;
    const int i = selector.SelectRemapped(light_point.v, &v);
    return {i, -1, selector.pmf[i], {light_point.u, v}};
}

// Receiver (p, n) of the tree; n = 0 in a medium (no horizon).
static inline ChosenLight ChooseLightFromTree(const RenderScene& scene, const Vec3f& p, const Vec3f& n,
                                              Point2<float> light_point) {
    const LightTreeSample s = scene.light_tree().Sample(p, n, light_point.v);
    if (s.emitter < 0 || !(s.pmf > 0)) return {};
    const TreeEmitterRef& ref = scene.light_tree_refs()[s.emitter];
    if (ref.kind == TreeEmitterKind::Delta) return {-1, ref.index, s.pmf, {light_point.u, s.u}};
    return {ref.index, -1, s.pmf, {light_point.u, s.u}};
}

// Whether light samples have an emitter to go to (otherwise only BSDF samples may be drawn).
static inline bool HasChoosableLights(const RenderScene& scene, LightSelection selection) {
    return selection == LightSelection::Tree ? !scene.light_tree().Empty() : !scene.light_selector.Empty();
}

// Delta lights evaluated once per camera sample (each casts its shadow ray): all of them with
// "power", only suns with "tree" (point and spot lights are tree emitters).
template <class F>
static inline void ForEachDeltaLightEvaluatedOnce(const RenderScene& scene, LightSelection selection, F&& f) {
    if (selection == LightSelection::Power) {
        for (const DeltaLight& d : scene.delta_lights) f(d);
    } else {
        for (uint32_t i : scene.sun_lights) f(scene.delta_lights[i]);
    }
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
    // normal: the techniques' (the cosine technique's horizon); tree_normal: the light tree's
    // receiver normal, (0,0,0) in a medium.
    LightSamplingAt(const RenderScene& scene, LightSelection selection, const Vec3f& origin, const Vec3f& normal,
                    const Vec3f& tree_normal)
        : scene_(scene), selection_(selection), origin_(origin), normal_(normal), tree_normal_(tree_normal) {}

    // The emitter of the light sample with pattern point light_point, at this receiver.
    ChosenLight Choose(Point2<float> light_point) const {
        if (selection_ == LightSelection::Tree) return ChooseLightFromTree(scene_, origin_, tree_normal_, light_point);
        return ChooseLightByPower(scene_.light_selector, light_point);
    }

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

    // Solid-angle pdf with which Sample, after Choose picked area light `index`, produces
    // point p on it: pmf(index) * pdf(p) (the tree's pmf at this receiver: area light i is tree
    // emitter i).
    float PDF(int index, const Vec3f& p) {
        const float pmf = selection_ == LightSelection::Tree ? scene_.light_tree().Pmf(origin_, tree_normal_, index)
                                                             : scene_.light_selector.pmf[index];
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
    LightSelection selection_;
    Vec3f origin_, normal_, tree_normal_;
    std::optional<LightSampler<K, float>> cached_;  // set up for rectangle light `cached_index_`
    int cached_index_ = -1;
    TriangleSolidAngleSetup triangle_;  // set up for triangle light `triangle_index_`
    int triangle_index_ = -1;
};

}  // namespace sphrect::render
