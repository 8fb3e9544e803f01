// Cycles 3.4's shadow terminator geometry offset (Blender's Object > Shading > Shadow Terminator > Geometry Offset,
// 0.1 by default; kernel/light/sample.h, shadow_ray_offset, after Hanika's "Hacking the Shadow Terminator", 2021):
// a smooth-shaded triangle lies inside the smooth surface its vertex normals describe, so near the terminator its
// light samples would be shadowed by the flat triangle and its neighbours where the smooth surface is lit.  Cycles
// moves such a sample's shadow-ray origin up to the smooth surface (a parabola through the triangle's vertices,
// within the envelope of the vertices' tangent planes) and traces light directions that lie below the flat triangle
// but above the shading normal's horizon.  Without the offset those directions are dropped (RayOriginTowards).
#pragma once

#include <algorithm>

#include "render/embree_rays.h"
#include "render/sampling_util.h"

namespace sphrect::render {

// The smooth surface's height above the hit along the interpolated normal, as a vector: vertices v, their normals
// n (as stored, unflipped), barycentrics b, ng the geometric normal on the side shading happens.
inline Vec3f SmoothSurfaceLift(const Vec3f (&v)[3], const Vec3f (&n)[3], const float (&b)[3], const Vec3f& ng) {
    const Vec3f p = v[0] * b[0] + v[1] * b[1] + v[2] * b[2];
    const Vec3f normal = n[0] * b[0] + n[1] * b[1] + n[2] * b[2];  // unnormalised, as Cycles
    // The parabola through the vertices whose slopes there are the normals' (Cycles' barycentrics u = b0, v = b1).
    const float a = Dot(n[2] - n[0], v[0] - v[2]), bb = Dot(n[2] - n[1], v[1] - v[2]),
                c = Dot(n[1] - n[0], v[1] - v[0]);
    const float u = b[0], w = b[1];
    float h = a * u * (u - 1) + (a + bb + c) * u * w + bb * w * (w - 1);
    // Bounded by the envelope of the vertices' tangent planes (on the side the normals face).
    const float sign = Dot(normal, ng) > 0 ? 1.0f : -1.0f;
    float envelope = kInf;
    for (int i = 0; i < 3; ++i) {
        const Vec3f& o1 = v[(i + 1) % 3];
        const Vec3f& o2 = v[(i + 2) % 3];
        const float rise = std::max(std::max(sign * Dot(o1 - v[i], n[i]), sign * Dot(o2 - v[i], n[i])), 0.0f);
        envelope = std::min(envelope, std::max(sign * Dot(v[i] - p, n[i]) + rise, 0.0f));
    }
    h = sign > 0 ? std::max(envelope, 0.5f * h) : std::min(-envelope, 0.5f * h);
    return normal * h;
}

// How much of the lift a light direction gets: cos_n and cos_ng its cosines to the shading and geometric normals
// (on the lit side), cutoff the offset.  1 at and below the flat triangle's horizon, fading to 0 away from the
// terminator (Cycles' smooth transition).
inline float TerminatorOffsetAmount(float cos_n, float cos_ng, float cutoff) {
    const float amount = cos_n < cutoff ? 2 - (cos_ng + cos_n) / cutoff : 1 - cos_ng / cutoff;
    return std::clamp(amount, 0.0f, 1.0f);
}

// The shadow ray's origin for a light direction with that amount: the lifted point, off the surface when the
// direction is above the flat triangle (Cycles skips the hit's own triangle there); below it, the ray is meant to
// meet the triangle, as in Cycles.
inline Vec3f TerminatorShadowOrigin(const Vec3f& p, const Vec3f& ng, const Vec3f& lift, float amount, float cos_ng) {
    const Vec3f lifted = p + lift * amount;
    return cos_ng > 0 ? OffsetOrigin(lifted, ng) : lifted;
}

}  // namespace sphrect::render
