// The checks a scene's Add*/Set* calls make of their input (scene*.cpp): std::invalid_argument with a readable
// message, which the bindings turn into ValueError.
#pragma once

#include <cmath>
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

}  // namespace sphrect::render
