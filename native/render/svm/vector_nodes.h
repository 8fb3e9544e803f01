// Vector converter nodes as Cycles 3.4 computes them (kernel/svm/mapping_util.h, util/transform.h): the Mapping node.
#pragma once

#include <cmath>

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

}  // namespace sphrect::render::svm
