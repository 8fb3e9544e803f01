// The ellipse (disk) light-sampling techniques behind one interface, as technique.h is for
// rectangles (a separate enum: the rectangle techniques' names are the renderer's options).
//
//   EllipseSampler<K, T> s(origin, normal, light);   // or (origin, normal, MakeEllipseLightFrame(light))
//   s.Valid(), s.Sample({u, v}) -> LightSample<T>, s.PDF(point_on_light)
#pragma once

#include <array>
#include <type_traits>

#include "ellipse_area.h"
#include "spherical_ellipse.h"

namespace sphrect {

enum class EllipseTechnique { Area, SphericalEllipse };

constexpr std::array<EllipseTechnique, 2> kAllEllipseTechniques = {EllipseTechnique::Area,
                                                                   EllipseTechnique::SphericalEllipse};

inline const char* EllipseTechniqueName(EllipseTechnique t) {
    switch (t) {
        case EllipseTechnique::Area: return "area";
        case EllipseTechnique::SphericalEllipse: return "spherical_ellipse";
    }
    return "?";
}

template <EllipseTechnique K, class T>
struct EllipseSampler;

template <class T>
struct EllipseSampler<EllipseTechnique::Area, T> {
    LocalEllipse<T> r;
    EllipseSampler(const Vec3<T>& origin, const Vec3<T>& /*normal*/, const EllipseLight<T>& light)
        : r(MakeLocalEllipse(origin, light)) {}
    EllipseSampler(const Vec3<T>& origin, const Vec3<T>& /*normal*/, const EllipseLightFrame<T>& frame)
        : r(MakeLocalEllipse(origin, frame)) {}
    bool Valid() const { return r.valid; }
    LightSample<T> Sample(Point2<T> uv) const { return SampleEllipseArea(r, uv); }
    T PDF(const Vec3<T>& p) const { return EllipseAreaPDF(r, p); }
};

template <class T>
struct EllipseSampler<EllipseTechnique::SphericalEllipse, T> {
    SphericalEllipseSetup<T> r;
    EllipseSampler(const Vec3<T>& origin, const Vec3<T>& /*normal*/, const EllipseLight<T>& light)
        : r(MakeSphericalEllipseSetup(origin, light)) {}
    EllipseSampler(const Vec3<T>& origin, const Vec3<T>& /*normal*/, const EllipseLightFrame<T>& frame)
        : r(MakeSphericalEllipseSetup(origin, frame)) {}
    bool Valid() const { return r.valid; }
    LightSample<T> Sample(Point2<T> uv) const { return SampleSphericalEllipse(r, uv); }
    T PDF(const Vec3<T>& p) const { return SphericalEllipsePDF(r, p); }
};

// Calls f(tag) with the technique as a compile-time value (tag::value).
template <class F>
decltype(auto) DispatchEllipseTechnique(EllipseTechnique t, F&& f) {
    if (t == EllipseTechnique::Area) return f(std::integral_constant<EllipseTechnique, EllipseTechnique::Area>{});
    return f(std::integral_constant<EllipseTechnique, EllipseTechnique::SphericalEllipse>{});
}

}  // namespace sphrect
