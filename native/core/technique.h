// The light-sampling techniques behind one interface, so the renderer and the
// bindings can be templated on the technique (no run-time branch per sample).
//
//   LightSampler<K, T> s(origin, normal, light);   // per (shading point, light) setup
//   LightSampler<K, T> s(origin, normal, frame);   // the same from MakeRectLightFrame(light),
//                                                  // computed once per light
//   s.Valid()                                      // false: every sample has pdf 0
//   s.Sample({u, v}) -> LightSample<T>
//   s.PDF(point_on_light) -> solid-angle pdf of choosing that point (for MIS)
//
// Each technique's setup, sample, pdf (and inverse) sit in the header named after it: area.h,
// triangles.h, rectangle.h, rectangle_cosine.h, rectangle_projected.h, rectangle_ltc.h (whose sampler also takes
// the shading point's glossy lobe: GlossyLobe).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <type_traits>

#include "area.h"
#include "enum_names.h"
#include "rectangle.h"
#include "rectangle_cosine.h"
#include "rectangle_ltc.h"
#include "rectangle_projected.h"
#include "triangles.h"

namespace sphrect {

enum class Technique { Area, Triangles, Rectangle, RectangleCosine, RectangleProjected, RectangleLtc };

constexpr std::array<Technique, 6> kAllTechniques = {Technique::Area,
                                                     Technique::Triangles,
                                                     Technique::Rectangle,
                                                     Technique::RectangleCosine,
                                                     Technique::RectangleProjected,
                                                     Technique::RectangleLtc};

inline const char* TechniqueName(Technique t) {
    switch (t) {
        case Technique::Area: return "area";
        case Technique::Triangles: return "triangles";
        case Technique::Rectangle: return "rectangle";
        case Technique::RectangleCosine: return "rectangle_cosine";
        case Technique::RectangleProjected: return "rectangle_projected";
        case Technique::RectangleLtc: return "rectangle_ltc";
    }
    return "?";
}

template <Technique K, class T>
struct LightSampler;

template <class T>
struct LightSampler<Technique::Area, T> {
    LocalRect<T> r;
    LightSampler(const Vec3<T>& origin, const Vec3<T>& /*normal*/, const RectLight<T>& light)
        : r(MakeLocalRect(origin, light)) {}
    LightSampler(const Vec3<T>& origin, const Vec3<T>& /*normal*/, const RectLightFrame<T>& frame)
        : r(MakeLocalRect(origin, frame)) {}
    bool Valid() const { return r.valid; }
    LightSample<T> Sample(Point2<T> uv) const { return SampleArea(r, uv); }
    T PDF(const Vec3<T>& p) const { return AreaPDF(r, p); }
};

template <class T>
struct LightSampler<Technique::Triangles, T> {
    TrianglesSetup<T> r;
    LightSampler(const Vec3<T>& origin, const Vec3<T>& /*normal*/, const RectLight<T>& light)
        : r(MakeTrianglesSetup(origin, light)) {}
    LightSampler(const Vec3<T>& origin, const Vec3<T>& /*normal*/, const RectLightFrame<T>& frame)
        : r(MakeTrianglesSetup(origin, frame)) {}
    bool Valid() const { return r.valid; }
    LightSample<T> Sample(Point2<T> uv) const { return SampleTriangles(r, uv); }
    T PDF(const Vec3<T>& p) const { return TrianglesPDF(r, p); }
};

template <class T>
struct LightSampler<Technique::Rectangle, T> {
    RectangleSetup<T> r;
    LightSampler(const Vec3<T>& origin, const Vec3<T>& /*normal*/, const RectLight<T>& light)
        : r(MakeRectangleSetup(origin, light)) {}
    LightSampler(const Vec3<T>& origin, const Vec3<T>& /*normal*/, const RectLightFrame<T>& frame)
        : r(MakeRectangleSetup(origin, frame)) {}
    bool Valid() const { return r.valid; }
    LightSample<T> Sample(Point2<T> uv) const { return SampleRectangle(r, uv); }
    T PDF(const Vec3<T>& p) const { return RectanglePDF(r, p); }
};

template <class T>
struct LightSampler<Technique::RectangleCosine, T> {
    RectangleCosineSetup<T> r;
    LightSampler(const Vec3<T>& origin, const Vec3<T>& normal, const RectLight<T>& light)
        : r(MakeRectangleCosineSetup(origin, normal, light)) {}
    LightSampler(const Vec3<T>& origin, const Vec3<T>& normal, const RectLightFrame<T>& frame)
        : r(MakeRectangleCosineSetup(origin, normal, frame)) {}
    bool Valid() const { return r.valid; }
    LightSample<T> Sample(Point2<T> uv) const { return SampleRectangleCosine(r, uv); }
    T PDF(const Vec3<T>& p) const { return RectangleCosinePDF(r, p); }
};

template <class T>
struct LightSampler<Technique::RectangleProjected, T> {
    RectangleProjectedSetup<T> r;
    LightSampler(const Vec3<T>& origin, const Vec3<T>& normal, const RectLight<T>& light)
        : r(MakeRectangleProjectedSetup(origin, normal, light)) {}
    LightSampler(const Vec3<T>& origin, const Vec3<T>& normal, const RectLightFrame<T>& frame)
        : r(MakeRectangleProjectedSetup(origin, normal, frame)) {}
    bool Valid() const { return r.valid; }
    LightSample<T> Sample(Point2<T> uv) const { return SampleRectangleProjected(r, uv); }
    T PDF(const Vec3<T>& p) const { return RectangleProjectedPDF(r, p); }
};

// `rectangle_ltc`: a one-sample mixture of the glossy lobe's LTC map (rectangle_ltc.h) and rectangle_projected for the
// rest of the BSDF, chosen with the share of each in the light's reflected radiance as the LTC estimates it (Heitz et
// al. 2016: the LTC's integral over the light is E_o / pi, the cosine's E / pi): share = s E_o / (s E_o + d E),
// s and d the lobe's and the rest's weights, the rest kept at least kRectangleLtcMinProjectedShare so that every
// direction the BSDF reflects keeps a density without MIS (the LTC's support is not the lobe's).  The pdf is the
// mixture's at the returned point (the balance heuristic of the two, one sample).  Without a lobe (GlossyLobe's
// weights 0, as the three-argument constructors give) it samples as rectangle_projected.
constexpr double kRectangleLtcMinProjectedShare = 0.05;

template <class T>
struct LightSampler<Technique::RectangleLtc, T> {
    RectangleProjectedSetup<T> rest;
    RectangleLtcSetup<T> glossy;
    T share = 0;  // chance of the LTC map

    LightSampler(const Vec3<T>& origin, const Vec3<T>& normal, const RectLight<T>& light,
                 const GlossyLobe<T>& lobe = {})
        : LightSampler(origin, normal, MakeRectLightFrame(light), lobe) {}
    LightSampler(const Vec3<T>& origin, const Vec3<T>& normal, const RectLightFrame<T>& frame,
                 const GlossyLobe<T>& lobe = {})
        : rest(MakeRectangleProjectedSetup(origin, normal, frame)) {
        if (!rest.valid || !(lobe.weight > 0)) return;
        glossy = MakeRectangleLtcSetup(origin, normal, lobe.wo, lobe.alpha, frame, /*build_fallback=*/false);
        if (!glossy.valid || glossy.use_projected) return;  // the LTC's fallback is `rest` itself
        const double g = double(lobe.weight) * glossy.E, d = double(lobe.rest_weight) * rest.E;
        share = T(std::min(g / (g + d), 1 - kRectangleLtcMinProjectedShare));
        if (!(share > 0)) share = 0;
    }
    bool Valid() const { return rest.valid; }
    LightSample<T> Sample(Point2<T> uv) const {
        const T below_one = std::nextafter(T(1), T(0));  // (the rescaled u stays in [0, 1))
        LightSample<T> ls;
        if (uv.u < share) {
            ls = SampleRectangleLtc(glossy, {std::min(uv.u / share, below_one), uv.v});
        } else {
            ls = SampleRectangleProjected(rest, {std::min((uv.u - share) / (1 - share), below_one), uv.v});
        }
        if (share > 0 && ls.Valid()) ls.pdf = PDF(ls.point);  // (without a lobe: rectangle_projected's, as is)
        return ls;
    }
    T PDF(const Vec3<T>& p) const {
        const T projected = RectangleProjectedPDF(rest, p);
        return share > 0 ? share * RectangleLtcPDF(glossy, p) + (1 - share) * projected : projected;
    }
};

// The techniques weighted by the cosine at the shading point: they need its normal (and have no use in a medium).
constexpr bool NeedsShadingNormal(Technique t) {
    return t == Technique::RectangleCosine || t == Technique::RectangleProjected || t == Technique::RectangleLtc;
}

// Calls f(std::integral_constant-like tag) with the technique as a compile-time value.
template <class F>
decltype(auto) DispatchTechnique(Technique t, F&& f) {
    switch (t) {
        case Technique::Area: return f(std::integral_constant<Technique, Technique::Area>{});
        case Technique::Triangles: return f(std::integral_constant<Technique, Technique::Triangles>{});
        case Technique::Rectangle: return f(std::integral_constant<Technique, Technique::Rectangle>{});
        case Technique::RectangleCosine: return f(std::integral_constant<Technique, Technique::RectangleCosine>{});
        case Technique::RectangleProjected:
            return f(std::integral_constant<Technique, Technique::RectangleProjected>{});
        case Technique::RectangleLtc: break;
    }
    return f(std::integral_constant<Technique, Technique::RectangleLtc>{});
}

}  // namespace sphrect
