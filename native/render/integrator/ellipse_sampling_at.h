// Ellipse (disk) lights at one shading or scattering point (with spread: the clip of their bounding
// rectangle, SpreadClipDispatch), sampled with the ellipse technique the
// user chose (RenderOptions::ellipse_technique): `area`, uniformly by area (area_light.h, no setup),
// or `spherical_ellipse`, the area-preserving map of core/spherical_ellipse.h, following its area
// fallback (Sample and PDF both go through the setup, so the pdf is that of the point returned) --
// except where area sampling is already within kEllipseAreaMaxSpread of uniform in solid angle from
// this point (core/ellipse_map_choice.h: small or distant lights), which `spherical_ellipse` samples
// by area too, with no setup: there the map cannot pay for its cost.  The choice depends on (point,
// light) only, so Sample and PDF (also a BSDF/phase ray's MIS pdf) make the same one.
//
// The technique is a run-time branch on the ellipse path only, not a kernel template parameter (which
// would double the kernels compiled): a scene without ellipse lights never reaches this code (it pays
// two stores per shading point, the technique and the kept count), and a disk scene's branch is one
// well-predicted compare next to a spherical ellipse setup and map of thousands of instructions
// (the instruction counts: docs/ellipse_map.md section 10).
//
// A spherical ellipse's setup is made once per (point, light) -- by the first sample of that light or
// the first pdf a BSDF/phase ray needs of it -- and kept for the following samples and pdfs, like
// a rectangle's sampler in LightSamplingAt: up to kKeptEllipseSetups of them (a light sample's
// light and the one a paired BSDF ray hits), the oldest replaced.  No allocation: in place.
#pragma once

#include <algorithm>
#include <new>
#include <type_traits>

#include "core/ellipse_map_choice.h"
#include "core/ellipse_technique.h"
#include "core/technique.h"
#include "render/area_light.h"

namespace sphrect::render {

class EllipseSamplingAt {
    // With spread: the clip of the ellipse's bounding rectangle (SpreadClippedFrame), which holds the support of
    // its attenuated emission (the disc there within the ellipse), sampled as a rectangle light by area (`area`)
    // or by solid angle with the rectangle map (`spherical_ellipse`); f(sampler).  Set up at each call: spread
    // ellipses only.
    template <class F>
    auto SpreadClipDispatch(const AreaLight& l, const Vec3f& origin, F&& f) const {
        const RectLightFrame<float> clip = SpreadClippedFrame(l, origin);
        if (technique_ == EllipseTechnique::Area) return f(LightSampler<Technique::Area, float>(origin, {}, clip));
        return f(LightSampler<Technique::Rectangle, float>(origin, {}, clip));
    }
    // A sample of the clip, dropped off the ellipse (where nothing emits).
    template <class S>
    static LightSample<float> SampleOnEllipse(const AreaLight& l, const S& s, Point2<float> u) {
        if (!s.Valid()) return {};
        const LightSample<float> ls = s.Sample(u);
        return OnEllipse(l, ls.point) ? ls : LightSample<float>{};
    }

  public:
    explicit EllipseSamplingAt(EllipseTechnique technique) : technique_(technique) {}

    // A light sample on ellipse light l (area light `index`) seen from origin.
    LightSample<float> Sample(const AreaLight& l, int index, const Vec3f& origin, Point2<float> u) {
        if (l.HasSpread())
            return SpreadClipDispatch(l, origin, [&](const auto& s) { return SampleOnEllipse(l, s, u); });
        if (ByArea(l, origin)) return SampleEllipseArea(l, origin, u);
        return SampleSphericalEllipse(Setup(l, index, origin), u);
    }

    // Solid-angle pdf with which Sample produces point p on l.
    float PDF(const AreaLight& l, int index, const Vec3f& origin, const Vec3f& p) {
        if (l.HasSpread())
            return SpreadClipDispatch(l, origin, [&](const auto& s) { return s.Valid() ? s.PDF(p) : 0.0f; });
        if (ByArea(l, origin)) return EllipseAreaPDF(l, origin, p);
        return SphericalEllipsePDF(Setup(l, index, origin), p);
    }

  private:
    // Area sampling: the technique, or the spherical ellipse's choice where area sampling is nearly
    // uniform in solid angle (core/ellipse_map_choice.h).
    bool ByArea(const AreaLight& l, const Vec3f& origin) const {
        return technique_ == EllipseTechnique::Area || EllipseAreaSamplingSuffices(origin, l.ellipse_frame);
    }
    // Light `index`'s setup at origin (the same for every call of one EllipseSamplingAt).
    const SphericalEllipseSetup<float>& Setup(const AreaLight& l, int index, const Vec3f& origin) {
        const int kept = std::min(set_up_, kKeptEllipseSetups);
        for (int k = 0; k < kept; ++k)
            if (setup_index_[k] == index) return setup_[k].setup;
        const int slot = set_up_++ % kKeptEllipseSetups;
        setup_index_[slot] = index;
        return *new (&setup_[slot].setup)
            SphericalEllipseSetup<float>(MakeSphericalEllipseSetup(origin, l.ellipse_frame));
    }

    static constexpr int kKeptEllipseSetups = 2;
    // Left uninitialised until set up (~400 bytes each: zeroing them would cost every shading point).
    union SetupSlot {
        SetupSlot() {}
        SphericalEllipseSetup<float> setup;
    };
    static_assert(std::is_trivially_destructible_v<SphericalEllipseSetup<float>>, "slots are never destroyed");

    EllipseTechnique technique_;
    int set_up_ = 0;  // setups made at this point (slots k < min(set_up_, kKeptEllipseSetups) are set)
    int setup_index_[kKeptEllipseSetups];
    SetupSlot setup_[kKeptEllipseSetups];
};

}  // namespace sphrect::render
