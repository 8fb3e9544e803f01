// Microfacet distributions: GGX / Trowbridge-Reitz (isotropic and anisotropic) and Beckmann, their masking
// functions, visible-normal sampling and reflection pdfs, in the shading frame (normal +z).
#pragma once

#include <cmath>

#include "principled_lobes.h"
#include "render/sampling_util.h"

namespace sphrect::render {

// --- GGX / Trowbridge-Reitz (Walter et al. 2007; Heitz 2014, 2018) ---------------------------

inline float GgxD(const Vec3f& h, float alpha) {
    const float c2 = h.z * h.z, a2 = alpha * alpha;
    const float d = c2 * (a2 - 1) + 1;
    return a2 / (kPi * d * d);
}

// Smith Lambda for GGX: (-1 + sqrt(1 + alpha^2 tan^2 theta)) / 2.
inline float GgxLambda(const Vec3f& w, float alpha) {
    const float c2 = w.z * w.z;
    if (c2 <= 0) return kInf;
    const float tan2 = std::max(0.0f, 1 - c2) / c2;
    return 0.5f * (-1 + std::sqrt(1 + alpha * alpha * tan2));
}

inline float GgxG1(const Vec3f& w, float alpha) { return 1 / (1 + GgxLambda(w, alpha)); }
inline float GgxG2(const Vec3f& wo, const Vec3f& wi, float alpha) {
    return 1 / (1 + GgxLambda(wo, alpha) + GgxLambda(wi, alpha));
}

inline Spectrum SchlickFresnel(const Spectrum& f0, float cos_theta) {
    const float m = std::clamp(1 - cos_theta, 0.0f, 1.0f);
    const float m5 = (m * m) * (m * m) * m;
    return f0 + (Spectrum(1, 1, 1) - f0) * m5;
}

// Heitz 2018, "Sampling the GGX Distribution of Visible Normals": a microfacet normal with
// density D_wo(h) = G1(wo) max(0, wo.h) D(h) / wo.z.
// ax, ay: the roughness along x and y (anisotropic; equal: isotropic).
inline Vec3f SampleGgxVisibleNormal(const Vec3f& wo, float ax, float ay, Point2<float> u) {
    const Vec3f vh = Normalize(Vec3f(ax * wo.x, ay * wo.y, wo.z));
    const float len2 = vh.x * vh.x + vh.y * vh.y;
    const Vec3f t1 = len2 > 0 ? Vec3f(-vh.y, vh.x, 0) / std::sqrt(len2) : Vec3f(1, 0, 0);
    const Vec3f t2 = Cross(vh, t1);
    const float r = std::sqrt(u.u), phi = 2 * kPi * u.v;
    const float p1 = r * std::cos(phi);
    float p2 = r * std::sin(phi);
    const float s = 0.5f * (1 + vh.z);
    p2 = (1 - s) * SafeSqrt(1 - p1 * p1) + s * p2;
    const Vec3f nh = t1 * p1 + t2 * p2 + vh * SafeSqrt(1 - p1 * p1 - p2 * p2);
    return Normalize(Vec3f(ax * nh.x, ay * nh.y, std::max(1e-6f, nh.z)));
}
inline Vec3f SampleGgxVisibleNormal(const Vec3f& wo, float alpha, Point2<float> u) {
    return SampleGgxVisibleNormal(wo, alpha, alpha, u);
}

// Solid-angle pdf of wi = reflect(wo, h) when h is drawn from the visible normals:
// D_wo(h) / (4 wo.h) = G1(wo) D(h) / (4 wo.z).
inline float GgxReflectionPDF(const Vec3f& wo, const Vec3f& wi, float alpha) {
    if (wi.z <= 0) return 0;
    const Vec3f h = Normalize(wo + wi);
    return GgxG1(wo, alpha) * GgxD(h, alpha) / (4 * wo.z);
}

// --- Anisotropic GGX, as Cycles 3.4's bsdf_microfacet_ggx for alpha_x != alpha_y ----------------------
// In the frame of the lobe's tangent: x along it, z the normal (Cycles' make_orthonormals_tangent); (c, s) the
// tangent's cos and sin in the shading frame.
inline Vec3f IntoTangentFrame(const Vec3f& w, float c, float s) { return {c * w.x + s * w.y, c * w.y - s * w.x, w.z}; }
inline Vec3f OutOfTangentFrame(const Vec3f& w, float c, float s) { return {c * w.x - s * w.y, s * w.x + c * w.y, w.z}; }

// Smith G1 with the roughness projected on w's azimuth, alpha^2 = cos^2 phi ax^2 + sin^2 phi ay^2 (Cycles'
// separable G1: 2 / (1 + sqrt(1 + alpha^2 tan^2))).
inline float SmithG1GgxAnisotropic(const Vec3f& w, float ax, float ay) {
    const float z2 = w.z * w.z;
    if (!(z2 > 0)) return 0;
    return 2 / (1 + SafeSqrt(1 + (w.x * w.x * ax * ax + w.y * w.y * ay * ay) / z2));
}

// Solid-angle pdf of wi = reflect(wo, h), h from the visible normals (tangent frame): G1(wo) D(h) / (4 wo.z).
inline float GgxAnisotropicReflectionPDF(const Vec3f& wo, const Vec3f& wi, float ax, float ay) {
    if (wi.z <= 0) return 0;
    return SmithG1GgxAnisotropic(wo, ax, ay) * GgxAnisotropicD(Normalize(wo + wi), ax, ay) / (4 * wo.z);
}

// An anisotropic lobe's D G1 G1, and its sampling pdf, in the shading frame.
inline float GgxAnisotropicDG(const Vec3f& wo, const Vec3f& wi, const Vec3f& h, float ax, float ay, float c, float s) {
    const Vec3f o = IntoTangentFrame(wo, c, s), i = IntoTangentFrame(wi, c, s);
    return GgxAnisotropicD(IntoTangentFrame(h, c, s), ax, ay) * SmithG1GgxAnisotropic(o, ax, ay) *
           SmithG1GgxAnisotropic(i, ax, ay);
}
inline float GgxAnisotropicPDF(const Vec3f& wo, const Vec3f& wi, float ax, float ay, float c, float s) {
    return GgxAnisotropicReflectionPDF(IntoTangentFrame(wo, c, s), IntoTangentFrame(wi, c, s), ax, ay);
}
inline Vec3f SampleGgxAnisotropicNormal(const Vec3f& wo, float ax, float ay, float c, float s, Point2<float> u) {
    return OutOfTangentFrame(SampleGgxVisibleNormal(IntoTangentFrame(wo, c, s), ax, ay, u), c, s);
}

// --- Beckmann, as Cycles 3.4's bsdf_microfacet_beckmann (isotropic) --------------------------------

inline float BeckmannD(const Vec3f& h, float alpha) {
    const float c2 = h.z * h.z, a2 = alpha * alpha;
    if (c2 <= 0) return 0;
    const float tan2 = std::max(0.0f, 1 - c2) / c2;
    return std::exp(-tan2 / a2) / (kPi * a2 * c2 * c2);
}

// Cycles' bsdf_beckmann_G1: Walter et al. 2007's rational approximation of Smith's G1.
inline float BeckmannG1(float cos_theta, float alpha) {
    const float c2 = cos_theta * cos_theta;
    const float inv_a = alpha * SafeSqrt((1 - c2) / c2);
    if (inv_a < 0.0625f) return 1;
    const float a = 1 / inv_a;
    if (a >= 1.6f) return 1;
    return (3.535f * a + 2.181f * a * a) / (1 + 2.276f * a + 2.577f * a * a);
}

}  // namespace sphrect::render
