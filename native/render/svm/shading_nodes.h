// Cycles 3.4's shading-input nodes as pure functions: Layer Weight, Fresnel, Light Falloff (kernel/svm/fresnel.h,
// light_path.h) and Bump (kernel/svm/displace.h svm_node_set_bump, with the compact ray differentials of
// kernel/util/differential.h).  They read the shading point as Cycles' ShaderData holds it:
//   I           unit vector from the point towards where the ray came from (-ray direction);
//   N           the shading normal (smooth-interpolated, normal-mapped), flipped with Ng to the ray's side when the
//               ray hits the back of the triangle, which sets `backfacing`;
//   Ng          the geometric normal, flipped likewise;
//   ray_length  see LightFalloff;
//   dP          the point's differential radius (see BumpOffsets).
// A node's Normal input, when linked, replaces N as given (not normalised: Cycles takes it as it comes).
// Tested against Cycles per node in tests/blender/test_color_nodes.py.
#pragma once

#include <algorithm>
#include <cmath>

#include "core/vec3.h"
#include "render/bsdf/principled_lobes.h"  // DielectricFresnel: Cycles' fresnel_dielectric_cos

namespace sphrect::render::svm {

// Fresnel node: the reflectance for IOR `ior` (at least 1e-5), inverted on a back face.
inline float FresnelNode(float ior, const Vec3f& I, const Vec3f& N, bool backfacing) {
    float eta = std::max(ior, 1e-5f);
    eta = backfacing ? 1.0f / eta : eta;
    return DielectricFresnel(Dot(I, N), eta);
}

// Layer Weight's Fresnel output: the reflectance of relative IOR 1 / (1 - blend) (blend 0.5: IOR 2), its inverse
// on a back face.
inline float LayerWeightFresnel(float blend, const Vec3f& I, const Vec3f& N, bool backfacing) {
    float eta = std::max(1.0f - blend, 1e-5f);
    eta = backfacing ? eta : 1.0f / eta;
    return DielectricFresnel(Dot(I, N), eta);
}

// Layer Weight's Facing output: 1 - |I.N|^p, p = 2 blend below 0.5 and 0.5 / (1 - blend) above (blend clamped to
// [0, 1 - 1e-5]); blend exactly 0.5 skips the power (p = 1).
inline float LayerWeightFacing(float blend, const Vec3f& I, const Vec3f& N) {
    float f = std::abs(Dot(I, N));
    if (blend != 0.5f) {
        blend = std::clamp(blend, 0.0f, 1.0f - 1e-5f);
        blend = blend < 0.5f ? 2.0f * blend : 0.5f / (1.0f - blend);
        f = std::pow(f, blend);
    }
    return 1.0f - f;
}

// Light Falloff's outputs, by their socket names.
enum class LightFalloffKind { kQuadratic, kLinear, kConstant };
inline constexpr const char* kLightFalloffKindNames[] = {"Quadratic", "Linear", "Constant"};

// Light Falloff: strength times ray_length^0, ^1 or ^2 (Quadratic, Linear, Constant: the emitter's own 1/r^2 then
// leaves 1/r^2, 1/r or none), times r^2 / (smooth + r^2) when smooth > 0 (skipped where r^2 overflows, as a sun's
// FLT_MAX length does).  What ray_length is, as Cycles sets sd->ray_length:
//   camera rays: the distance from where the ray starts -- on the near clipping plane (perspective: the eye point
//     moved clip_start / cos along the ray; orthographic: the film point on the plane z = clip_start) -- to the hit;
//   light samples on an emissive mesh, lamp or area light: the distance from the shading point to the sampled
//     point (ls->t); a sun: FLT_MAX;
//   BSDF (and shadow) rays hitting an emitter: the distance from the shading point to the hit (isect.t);
//   the world background: 0.
inline float LightFalloff(LightFalloffKind kind, float strength, float smooth, float ray_length) {
    if (kind == LightFalloffKind::kLinear) strength *= ray_length;
    if (kind == LightFalloffKind::kConstant) strength *= ray_length * ray_length;
    if (smooth > 0.0f) {
        const float squared = ray_length * ray_length;
        if (std::isfinite(squared)) strength *= squared / (smooth + squared);
    }
    return strength;
}

// ---- Bump ------------------------------------------------------------------------------------------------------

// Cycles' make_orthonormals: two unit vectors completing n (unit) to a frame, from (1,1,1) x n (or (-1,1,1) x n
// when n's components are equal).
inline void MakeOrthonormals(const Vec3f& n, Vec3f* a, Vec3f* b) {
    *a = (n.x != n.y || n.x != n.z) ? Vec3f(n.z - n.y, n.x - n.z, n.y - n.x) : Vec3f(n.z - n.y, n.x + n.z, -n.y - n.x);
    *a = Normalize(*a);
    *b = Cross(n, *a);
}

// The surface differentials Cycles 3.4 bumps with.  Its ray differentials are compact (a radius, not two vectors):
// the point's dP = ray dP + t ray dD (camera rays: orthographic dP = the length of one pixel's step on the film,
// dD = 0; perspective: dD = the mean length of a pixel's change of the unit direction, dP its part up to the near
// plane, so that the point's dP = (its distance from the eye) dD; BSDF and light rays carry their own), and the
// differentials are dP times the two vectors MakeOrthonormals gives the (flipped) geometric normal Ng.  The Bump
// node's height input is evaluated three times:
// at the point (centre) and with every position-dependent input (Texture Coordinate Object/Generated/Camera/Window,
// Geometry Position, Attribute) read at P + dx and at P + dy (UVs likewise shifted by their du/dv).
struct BumpOffsets {
    Vec3f dx, dy;
};
inline BumpOffsets BumpDifferentials(const Vec3f& Ng, float dP) {
    Vec3f a, b;
    MakeOrthonormals(Ng, &a, &b);
    return {a * dP, b * dP};
}

// ensure_valid_reflection's test: whether the reflection of I about N stays above the surface, at least
// min(0.9 I.Ng, 0.01) along Ng.
inline float ValidReflectionThreshold(const Vec3f& Ng, const Vec3f& I) { return std::min(0.9f * Dot(Ng, I), 0.01f); }
inline bool ReflectionIsValid(const Vec3f& Ng, const Vec3f& I, const Vec3f& N) {
    const Vec3f R = N * (2 * Dot(N, I)) - I;
    return Dot(Ng, R) >= ValidReflectionThreshold(Ng, I);
}

// Cycles' ensure_valid_reflection: N where ReflectionIsValid, else N turned towards Ng just enough that it is; Ng
// when no such N exists.
inline Vec3f EnsureValidReflection(const Vec3f& Ng, const Vec3f& I, const Vec3f& N) {
    if (ReflectionIsValid(Ng, I, N)) return N;
    const float threshold = ValidReflectionThreshold(Ng, I);
    const float n_dot_ng = Dot(N, Ng);
    const Vec3f X = Normalize(N - Ng * n_dot_ng);
    const float ix = Dot(I, X), iz = Dot(I, Ng);
    const float ix2 = ix * ix, iz2 = iz * iz, a = ix2 + iz2;
    const auto safe_sqrt = [](float x) { return std::sqrt(std::max(x, 0.0f)); };
    const float b = safe_sqrt(ix2 * (a - threshold * threshold));
    const float c = iz * threshold + a;
    const float fac = 0.5f / a;
    const float n1_z2 = fac * (b + c), n2_z2 = fac * (-b + c);
    bool valid1 = n1_z2 > 1e-5f && n1_z2 <= 1.0f + 1e-5f;
    bool valid2 = n2_z2 > 1e-5f && n2_z2 <= 1.0f + 1e-5f;
    float nx, nz;
    if (valid1 && valid2) {
        const float n1x = safe_sqrt(1.0f - n1_z2), n1z = safe_sqrt(n1_z2);
        const float n2x = safe_sqrt(1.0f - n2_z2), n2z = safe_sqrt(n2_z2);
        const float r1 = 2 * (n1x * ix + n1z * iz) * n1z - iz, r2 = 2 * (n2x * ix + n2z * iz) * n2z - iz;
        valid1 = r1 >= 1e-5f;
        valid2 = r2 >= 1e-5f;
        const bool first = (valid1 && valid2) ? r1 < r2 : r1 > r2;
        nx = first ? n1x : n2x;
        nz = first ? n1z : n2z;
    } else if (valid1 || valid2) {
        const float z2 = valid1 ? n1_z2 : n2_z2;
        nx = safe_sqrt(1.0f - z2);
        nz = safe_sqrt(z2);
    } else {
        return Ng;
    }
    return X * nx + Ng * nz;
}

// Bump node (world space): the normal N (the Normal input, or the shading normal) tilted by the height's surface
// gradient from its three samples (h_c at the point, h_x at P + dx, h_y at P + dy: BumpDifferentials), scaled by
// distance (negated by invert), blended with N by strength (clamped at 0), then kept valid for reflection.
// Object-space bump (use_object_space, set only by displacement's automatic bump) is not covered.
inline Vec3f BumpNormal(const Vec3f& N, const Vec3f& Ng, const Vec3f& I, const BumpOffsets& d, float h_c, float h_x,
                        float h_y, float strength, float distance, bool invert) {
    const Vec3f rx = Cross(d.dy, N), ry = Cross(N, d.dx);
    const float det = Dot(d.dx, rx);
    const Vec3f surfgrad = rx * (h_x - h_c) + ry * (h_y - h_c);
    const float absdet = std::abs(det);
    const float scale = invert ? -distance : distance;
    strength = std::max(strength, 0.0f);
    const float sign = det < 0.0f ? -1.0f : 1.0f;  // Cycles' signf: 1 at 0
    Vec3f out = N * absdet - surfgrad * (scale * sign);
    const float len = Length(out);
    if (len != 0.0f) out = out * (1.0f / len);
    if (out.x == 0.0f && out.y == 0.0f && out.z == 0.0f)
        out = N;
    else
        out = Normalize(out * strength + N * (1.0f - strength));
    return EnsureValidReflection(Ng, I, out);
}

}  // namespace sphrect::render::svm
