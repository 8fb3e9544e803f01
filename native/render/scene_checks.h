// The checks a scene's Add*/Set* calls make of their input (scene*.cpp): std::invalid_argument with a readable
// message, which the bindings turn into ValueError.
#pragma once

#include <cmath>
#include <embree3/rtcore.h>

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "sampling_util.h"

namespace sphrect::render {

[[noreturn]] inline void Fail(const std::string& what) { throw std::invalid_argument(what); }

inline bool NonNegative(const Spectrum& c) { return c.x >= 0 && c.y >= 0 && c.z >= 0; }

inline void CheckColor(const std::string& what, const Spectrum& c) {
    if (!IsFinite(c) || !NonNegative(c)) Fail(what + " must be finite and non-negative");
}

inline void CheckVector(const std::string& what, const Vec3f& v) {
    if (!IsFinite(v)) Fail(what + " must be finite");
}

// A triangle mesh's arrays (3 floats per vertex, 3 indices per triangle), std::invalid_argument naming `who`: not too
// large, finite vertices inside Embree's range, every index a vertex's (scene_geometry.cpp).
void CheckTriangleMesh(const std::string& who, const float* vertices, size_t nv, const int32_t* triangles, size_t nt);

// A new Embree triangle geometry holding a copy of the arrays (nt > 0), its buffers in *vertex_buffer and
// *index_buffer where given (scene_geometry.cpp).
RTCGeometry NewTriangleGeometry(RTCDevice device, const std::string& who, const float* vertices, size_t nv,
                                const int32_t* triangles, size_t nt, const float** vertex_buffer = nullptr,
                                const uint32_t** index_buffer = nullptr);

}  // namespace sphrect::render
