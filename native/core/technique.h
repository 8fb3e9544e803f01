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
// triangles.h, rectangle.h, rectangle_cosine.h, rectangle_projected.h.
#pragma once

#include <array>
#include <type_traits>

#include "area.h"
#include "enum_names.h"
#include "rectangle.h"
#include "rectangle_cosine.h"
#include "rectangle_projected.h"
#include "triangles.h"

namespace sphrect {

enum class Technique { Area, Triangles, Rectangle, RectangleCosine, RectangleProjected };

constexpr std::array<Technique, 5> kAllTechniques = {Technique::Area, Technique::Triangles, Technique::Rectangle,
                                                     Technique::RectangleCosine, Technique::RectangleProjected};

inline const char* TechniqueName(Technique t) {
    switch (t) {
        case Technique::Area: return "area";
        case Technique::Triangles: return "triangles";
        case Technique::Rectangle: return "rectangle";
        case Technique::RectangleCosine: return "rectangle_cosine";
        case Technique::RectangleProjected: return "rectangle_projected";
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

// Calls f(std::integral_constant-like tag) with the technique as a compile-time value.
template <class F>
decltype(auto) DispatchTechnique(Technique t, F&& f) {
    switch (t) {
        case Technique::Area: return f(std::integral_constant<Technique, Technique::Area>{});
        case Technique::Triangles: return f(std::integral_constant<Technique, Technique::Triangles>{});
        case Technique::Rectangle: return f(std::integral_constant<Technique, Technique::Rectangle>{});
        case Technique::RectangleCosine: return f(std::integral_constant<Technique, Technique::RectangleCosine>{});
        case Technique::RectangleProjected: break;
    }
    return f(std::integral_constant<Technique, Technique::RectangleProjected>{});
}

}  // namespace sphrect
