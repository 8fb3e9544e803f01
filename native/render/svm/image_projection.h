// The Image Texture node's projections as Cycles 3.4 computes them (kernel/svm/image.h svm_node_tex_image and
// svm_node_tex_image_box, util/math.h map_to_sphere / map_to_tube): the point a vector reads of the image.
#pragma once

#include <algorithm>
#include <cmath>

#include "core/vec3.h"
#include "render/sampling_util.h"

namespace sphrect::render::svm {

// The node's projection, Blender's identifiers (kImageProjectionNames' order).
enum class ImageProjection : uint8_t { kFlat, kBox, kSphere, kTube, kCount };
constexpr const char* kImageProjectionNames[] = {"FLAT", "BOX", "SPHERE", "TUBE"};

// Sphere and Tube read the vector remapped from the unit box [0, 1]^3 to [-1, 1]^3 (texco_remap_square).
inline Vec3f RemapSquare(const Vec3f& co) { return (co - Vec3f(0.5f, 0.5f, 0.5f)) * 2.0f; }

// Longitude about +Z (u, from -Y around through +X) and latitude (v, 0 at the bottom) of the direction co.
inline Vec3f MapToSphere(const Vec3f& co) {
    const float l = Dot(co, co);
    if (!(l > 0.0f)) return {};
    const float u = (co.x == 0.0f && co.y == 0.0f) ? 0.0f : 0.5f - std::atan2(co.x, co.y) * (0.5f * kInvPi);
    const float c = std::clamp(co.z / std::sqrt(l), -1.0f, 1.0f);  // safe_acosf
    return {u, 1.0f - std::acos(c) * kInvPi, 0.0f};
}

// Longitude about +Z as MapToSphere's, and the height z from [-1, 1] to [0, 1].
inline Vec3f MapToTube(const Vec3f& co) {
    const float len = std::sqrt(co.x * co.x + co.y * co.y);
    if (!(len > 0.0f)) return {};
    return {(1.0f - std::atan2(co.x / len, co.y / len) * kInvPi) * 0.5f, (co.z + 1.0f) * 0.5f, 0.0f};
}

// Box projection's weights of the images seen along X, Y and Z at object-space normal n (any length): a lone face's
// image near the axes, two or three blended over `blend` (0: the dominant axis alone).
inline Vec3f BoxProjectionWeights(const Vec3f& n, float blend) {
    Vec3f N(std::abs(n.x), std::abs(n.y), std::abs(n.z));
    N = N / (N.x + N.y + N.z);
    const float limit = 0.5f * (1.0f + blend);
    auto saturate = [](float x) { return std::clamp(x, 0.0f, 1.0f); };
    if (N.x > limit * (N.x + N.y) && N.x > limit * (N.x + N.z)) return {1, 0, 0};
    if (N.y > limit * (N.x + N.y) && N.y > limit * (N.y + N.z)) return {0, 1, 0};
    if (N.z > limit * (N.x + N.z) && N.z > limit * (N.y + N.z)) return {0, 0, 1};
    if (!(blend > 0.0f)) return {1, 0, 0};  // no valid choice: Cycles falls back to X
    if (N.z < (1.0f - limit) * (N.y + N.x)) {
        const float x = saturate((N.x / (N.x + N.y) - 0.5f * (1.0f - blend)) / blend);
        return {x, 1.0f - x, 0};
    }
    if (N.x < (1.0f - limit) * (N.y + N.z)) {
        const float y = saturate((N.y / (N.y + N.z) - 0.5f * (1.0f - blend)) / blend);
        return {0, y, 1.0f - y};
    }
    if (N.y < (1.0f - limit) * (N.x + N.z)) {
        const float x = saturate((N.x / (N.x + N.z) - 0.5f * (1.0f - blend)) / blend);
        return {x, 0, 1.0f - x};
    }
    const float k = 2.0f * limit - 1.0f;
    return {((2.0f - limit) * N.x + (limit - 1.0f)) / k, ((2.0f - limit) * N.y + (limit - 1.0f)) / k,
            ((2.0f - limit) * N.z + (limit - 1.0f)) / k};
}

// The image coordinates box projection reads for axis `axis` (0 X, 1 Y, 2 Z) of vector co, at object-space normal n
// (mirrored so that no face's image is flipped).
inline Vec3f BoxProjectionPoint(int axis, const Vec3f& co, const Vec3f& n) {
    if (axis == 0) return {n.x < 0.0f ? 1.0f - co.y : co.y, co.z, 0.0f};
    if (axis == 1) return {n.y > 0.0f ? 1.0f - co.x : co.x, co.z, 0.0f};
    return {n.z > 0.0f ? 1.0f - co.y : co.y, co.x, 0.0f};
}

}  // namespace sphrect::render::svm
