// The light-sampling techniques behind one interface, so the renderer and the
// bindings can be templated on the technique (no run-time branch per sample).
//
//   LightSampler<K, T> s(origin, normal, light);   // per (shading point, light) setup
//   LightSampler<K, T> s(origin, normal, frame);   // the same from MakeRectLightFrame(light),
//                                                  // computed once per light
//   s.Valid()                                      // false: every sample has pdf 0
//   s.Sample({u, v}) -> LightSample<T>
//   s.Pdf(point_on_light) -> solid-angle pdf of choosing that point (for MIS)
#pragma once

#include <array>
#include <cstring>
#include <type_traits>
#include <string>

#include "area_sampling.h"
#include "enum_names.h"
#include "rectangle_cosine.h"
#include "spherical_rectangle.h"
#include "triangles_sampling.h"

namespace sphrect {

enum class Technique { Area, Triangles, Rectangle, RectangleCosine };

constexpr std::array<Technique, 4> kAllTechniques = {Technique::Area, Technique::Triangles, Technique::Rectangle,
                                                     Technique::RectangleCosine};

inline const char* TechniqueName(Technique t) {
    switch (t) {
        case Technique::Area: return "area";
        case Technique::Triangles: return "triangles";
        case Technique::Rectangle: return "rectangle";
        case Technique::RectangleCosine: return "rectangle_cosine";
    }
    return "?";
}

// False when `name` is not a technique.
inline bool ParseTechnique(const std::string& name, Technique* out) {
    return ParseEnumName(name, kAllTechniques, TechniqueName, out);
}

template <Technique K, class T>
struct LightSampler;

template <class T>
struct LightSampler<Technique::Area, T> {
    AreaRect<T> r;
    LightSampler(const Vec3<T>& origin, const Vec3<T>& /*normal*/, const RectLight<T>& light)
        : r(MakeAreaRect(origin, light)) {}
    LightSampler(const Vec3<T>& origin, const Vec3<T>& /*normal*/, const RectLightFrame<T>& frame)
        : r(MakeAreaRect(origin, frame)) {}
    bool Valid() const { return r.valid; }
    LightSample<T> Sample(Point2<T> uv) const { return SampleRectangleArea(r, uv); }
    T Pdf(const Vec3<T>& p) const { return RectangleAreaPDF(r, p); }
};

template <class T>
struct LightSampler<Technique::Triangles, T> {
    TwoTriangles<T> r;
    LightSampler(const Vec3<T>& origin, const Vec3<T>& /*normal*/, const RectLight<T>& light)
        : r(MakeTwoTriangles(origin, light)) {}
    LightSampler(const Vec3<T>& origin, const Vec3<T>& /*normal*/, const RectLightFrame<T>& frame)
        : r(MakeTwoTriangles(origin, frame)) {}
    bool Valid() const { return r.valid; }
    LightSample<T> Sample(Point2<T> uv) const { return SampleTwoTriangles(r, uv); }
    T Pdf(const Vec3<T>& p) const { return TwoTrianglesPDF(r, p); }
};

template <class T>
struct LightSampler<Technique::Rectangle, T> {
    SphericalRectangle<T> r;
    LightSampler(const Vec3<T>& origin, const Vec3<T>& /*normal*/, const RectLight<T>& light)
        : r(MakeSphericalRectangle(origin, light)) {}
    LightSampler(const Vec3<T>& origin, const Vec3<T>& /*normal*/, const RectLightFrame<T>& frame)
        : r(MakeSphericalRectangle(origin, frame)) {}
    bool Valid() const { return r.valid; }
    LightSample<T> Sample(Point2<T> uv) const { return SampleSphericalRectangle(r, uv); }
    T Pdf(const Vec3<T>& p) const { return SphericalRectanglePDF(r, p); }
};

template <class T>
struct LightSampler<Technique::RectangleCosine, T> {
    CosineRectangle<T> r;
    LightSampler(const Vec3<T>& origin, const Vec3<T>& normal, const RectLight<T>& light)
        : r(MakeCosineRectangle(origin, normal, light)) {}
    LightSampler(const Vec3<T>& origin, const Vec3<T>& normal, const RectLightFrame<T>& frame)
        : r(MakeCosineRectangle(origin, normal, frame)) {}
    bool Valid() const { return r.valid; }
    LightSample<T> Sample(Point2<T> uv) const { return SampleCosineRectangle(r, uv); }
    T Pdf(const Vec3<T>& p) const { return CosineRectanglePDF(r, p); }
};

// Calls f(std::integral_constant-like tag) with the technique as a compile-time value.
template <class F>
decltype(auto) DispatchTechnique(Technique t, F&& f) {
    switch (t) {
        case Technique::Area: return f(std::integral_constant<Technique, Technique::Area>{});
        case Technique::Triangles: return f(std::integral_constant<Technique, Technique::Triangles>{});
        case Technique::Rectangle: return f(std::integral_constant<Technique, Technique::Rectangle>{});
        case Technique::RectangleCosine: break;
    }
    return f(std::integral_constant<Technique, Technique::RectangleCosine>{});
}

}  // namespace sphrect
