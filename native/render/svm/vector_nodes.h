// Vector converter nodes as Cycles 3.4 computes them (kernel/svm/mapping_util.h, util/transform.h): the Mapping node.
#pragma once

#include <algorithm>
#include <cmath>

#include "math_nodes.h"  // MapRangeType
#include "render/sampling_util.h"

namespace sphrect::render::svm {

// The Mapping node's types, Blender's identifiers (vector_type), in kMappingTypeNames' order.
enum class MappingType : uint8_t { kPoint, kTexture, kVector, kNormal, kCount };
constexpr const char* kMappingTypeNames[] = {"POINT", "TEXTURE", "VECTOR", "NORMAL"};

// Cycles' euler_to_transform: the rotation of XYZ Euler angles, as three rows.
struct Rotation3 {
    Vec3f row[3];
    Vec3f Apply(const Vec3f& v) const { return {Dot(row[0], v), Dot(row[1], v), Dot(row[2], v)}; }
    Vec3f ApplyTransposed(const Vec3f& v) const { return row[0] * v.x + row[1] * v.y + row[2] * v.z; }
};
inline Rotation3 EulerRotation(const Vec3f& e) {
    const float cx = std::cos(e.x), cy = std::cos(e.y), cz = std::cos(e.z);
    const float sx = std::sin(e.x), sy = std::sin(e.y), sz = std::sin(e.z);
    return {{Vec3f(cy * cz, sy * sx * cz - cx * sz, sy * cx * cz + sx * sz),
             Vec3f(cy * sz, sy * sx * sz + cx * cz, sy * cx * sz - sx * cz), Vec3f(-sy, cy * sx, cy * cx)}};
}

inline Vec3f SafeDivide3(const Vec3f& a, const Vec3f& b) {
    return {b.x != 0.0f ? a.x / b.x : 0.0f, b.y != 0.0f ? a.y / b.y : 0.0f, b.z != 0.0f ? a.z / b.z : 0.0f};
}
inline Vec3f SafeNormalize3(const Vec3f& v) {
    const float len = Length(v);
    return len != 0.0f ? v / len : v;
}

inline Vec3f EvalMapping(MappingType type, const Vec3f& v, const Vec3f& location, const Vec3f& rotation,
                         const Vec3f& scale) {
    const Rotation3 r = EulerRotation(rotation);
    switch (type) {
        case MappingType::kPoint: return r.Apply(v * scale) + location;
        case MappingType::kTexture: return SafeDivide3(r.ApplyTransposed(v - location), scale);
        case MappingType::kVector: return r.Apply(v * scale);
        case MappingType::kNormal: return SafeNormalize3(r.Apply(SafeDivide3(v, scale)));
        case MappingType::kCount: break;
    }
    return {};
}

// The Map Range node on vectors (svm_node_vector_map_range): per component, a zero range giving factor 0 (not a
// result 0 as for floats), both smooth types without the float version's reversed-range case, and Clamp applied
// inside (ignored for the smooth types).
inline Vec3f EvalVectorMapRange(MapRangeType type, bool clamp, const Vec3f& value, const Vec3f& from_min,
                                const Vec3f& from_max, const Vec3f& to_min, const Vec3f& to_max, const Vec3f& steps) {
    Vec3f factor = SafeDivide3(value - from_min, from_max - from_min);
    auto stepped = [](float f, float n) { return n > 0.0f ? std::floor(f * (n + 1.0f)) / n : 0.0f; };
    auto unit = [](const Vec3f& f) {
        return Vec3f(std::clamp(f.x, 0.0f, 1.0f), std::clamp(f.y, 0.0f, 1.0f), std::clamp(f.z, 0.0f, 1.0f));
    };
    switch (type) {
        case MapRangeType::kStepped:
            factor = Vec3f(stepped(factor.x, steps.x), stepped(factor.y, steps.y), stepped(factor.z, steps.z));
            break;
        case MapRangeType::kSmoothstep:
            factor = unit(factor);
            factor = (Vec3f(3.0f, 3.0f, 3.0f) - factor * 2.0f) * (factor * factor);
            break;
        case MapRangeType::kSmootherstep:
            factor = unit(factor);
            factor = factor * factor * factor *
                     (factor * (factor * 6.0f - Vec3f(15.0f, 15.0f, 15.0f)) + Vec3f(10.0f, 10.0f, 10.0f));
            break;
        default: break;
    }
    Vec3f result = to_min + factor * (to_max - to_min);
    if (clamp && type != MapRangeType::kSmoothstep && type != MapRangeType::kSmootherstep) {
        auto range = [](float x, float a, float b) { return a > b ? std::clamp(x, b, a) : std::clamp(x, a, b); };
        result = Vec3f(range(result.x, to_min.x, to_max.x), range(result.y, to_min.y, to_max.y),
                       range(result.z, to_min.z, to_max.z));
    }
    return result;
}

}  // namespace sphrect::render::svm
