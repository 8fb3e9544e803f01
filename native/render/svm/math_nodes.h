// Converter nodes of scalars as Cycles 3.4 computes them (kernel/svm/math_util.h, map_range.h, clamp.h; the safe_*
// helpers of util/math.h): Math, Map Range, Clamp.  Pure functions of floats.
#pragma once

#include <algorithm>
#include <cfloat>
#include <cmath>

namespace sphrect::render::svm {

// The Math node's operations, Blender's identifiers (ShaderNodeMath.operation), in kMathOpNames' order.
enum class MathOp : uint8_t {
    kAdd,
    kSubtract,
    kMultiply,
    kDivide,
    kMultiplyAdd,
    kPower,
    kLogarithm,
    kSqrt,
    kInverseSqrt,
    kAbsolute,
    kExponent,
    kMinimum,
    kMaximum,
    kLessThan,
    kGreaterThan,
    kSign,
    kCompare,
    kSmoothMin,
    kSmoothMax,
    kRound,
    kFloor,
    kCeil,
    kTrunc,
    kFract,
    kModulo,
    kWrap,
    kSnap,
    kPingpong,
    kSine,
    kCosine,
    kTangent,
    kArcsine,
    kArccosine,
    kArctangent,
    kArctan2,
    kSinh,
    kCosh,
    kTanh,
    kRadians,
    kDegrees,
    kCount
};
constexpr const char* kMathOpNames[] = {
    "ADD",          "SUBTRACT",   "MULTIPLY",   "DIVIDE",   "MULTIPLY_ADD", "POWER",     "LOGARITHM",    "SQRT",
    "INVERSE_SQRT", "ABSOLUTE",   "EXPONENT",   "MINIMUM",  "MAXIMUM",      "LESS_THAN", "GREATER_THAN", "SIGN",
    "COMPARE",      "SMOOTH_MIN", "SMOOTH_MAX", "ROUND",    "FLOOR",        "CEIL",      "TRUNC",        "FRACT",
    "MODULO",       "WRAP",       "SNAP",       "PINGPONG", "SINE",         "COSINE",    "TANGENT",      "ARCSINE",
    "ARCCOSINE",    "ARCTANGENT", "ARCTAN2",    "SINH",     "COSH",         "TANH",      "RADIANS",      "DEGREES"};
static_assert(sizeof(kMathOpNames) / sizeof(*kMathOpNames) == size_t(MathOp::kCount));

constexpr float kPiF = 3.14159265358979323846f;

inline float SafeDivide(float a, float b) { return b != 0.0f ? a / b : 0.0f; }
inline float SafeModulo(float a, float b) { return b != 0.0f ? std::fmod(a, b) : 0.0f; }
inline float Fract(float x) { return x - std::floor(x); }
inline float Saturate(float x) { return std::min(std::max(x, 0.0f), 1.0f); }

// Cycles' safe_powf: no real power of a negative base to a fractional exponent (0 instead).
inline float SafePow(float a, float b) {
    if (a < 0.0f && b != float(int(b))) return 0.0f;
    return std::pow(a, b);
}
inline float SafeLog(float a, float b) {
    if (a <= 0.0f || b <= 0.0f) return 0.0f;
    return SafeDivide(std::log(a), std::log(b));
}
// Cycles' wrapf(value, max, min): value wrapped into [min, max).
inline float Wrap(float value, float max, float min) {
    const float range = max - min;
    return range != 0.0f ? value - range * std::floor((value - min) / range) : min;
}
inline float Pingpong(float a, float b) {
    return b != 0.0f ? std::fabs(Fract((a - b) / (b * 2.0f)) * b * 2.0f - b) : 0.0f;
}
// Polynomial smooth minimum of distance k.
inline float SmoothMin(float a, float b, float k) {
    if (k == 0.0f) return std::fmin(a, b);
    const float h = std::fmax(k - std::fabs(a - b), 0.0f) / k;
    return std::fmin(a, b) - h * h * h * k * (1.0f / 6.0f);
}
inline float SignOf(float f) { return f == 0.0f ? 0.0f : (f < 0.0f ? -1.0f : 1.0f); }

// The Math node (svm_math), before its Clamp option.
inline float EvalMath(MathOp op, float a, float b, float c) {
    switch (op) {
        case MathOp::kAdd: return a + b;
        case MathOp::kSubtract: return a - b;
        case MathOp::kMultiply: return a * b;
        case MathOp::kDivide: return SafeDivide(a, b);
        case MathOp::kMultiplyAdd: return a * b + c;
        case MathOp::kPower: return SafePow(a, b);
        case MathOp::kLogarithm: return SafeLog(a, b);
        case MathOp::kSqrt: return std::sqrt(std::max(a, 0.0f));
        case MathOp::kInverseSqrt: return a > 0.0f ? 1.0f / std::sqrt(a) : 0.0f;
        case MathOp::kAbsolute: return std::fabs(a);
        case MathOp::kExponent: return std::exp(a);
        case MathOp::kMinimum: return std::fmin(a, b);
        case MathOp::kMaximum: return std::fmax(a, b);
        case MathOp::kLessThan: return a < b ? 1.0f : 0.0f;
        case MathOp::kGreaterThan: return a > b ? 1.0f : 0.0f;
        case MathOp::kSign: return SignOf(a);
        case MathOp::kCompare: return (a == b || std::fabs(a - b) <= std::fmax(c, FLT_EPSILON)) ? 1.0f : 0.0f;
        case MathOp::kSmoothMin: return SmoothMin(a, b, c);
        case MathOp::kSmoothMax: return -SmoothMin(-a, -b, c);
        case MathOp::kRound: return std::floor(a + 0.5f);
        case MathOp::kFloor: return std::floor(a);
        case MathOp::kCeil: return std::ceil(a);
        case MathOp::kTrunc: return a >= 0.0f ? std::floor(a) : std::ceil(a);
        case MathOp::kFract: return Fract(a);
        case MathOp::kModulo: return SafeModulo(a, b);
        case MathOp::kWrap: return Wrap(a, b, c);
        case MathOp::kSnap: return std::floor(SafeDivide(a, b)) * b;
        case MathOp::kPingpong: return Pingpong(a, b);
        case MathOp::kSine: return std::sin(a);
        case MathOp::kCosine: return std::cos(a);
        case MathOp::kTangent: return std::tan(a);
        case MathOp::kArcsine: return std::asin(std::clamp(a, -1.0f, 1.0f));
        case MathOp::kArccosine: return std::acos(std::clamp(a, -1.0f, 1.0f));
        case MathOp::kArctangent: return std::atan(a);
        case MathOp::kArctan2: return std::atan2(a, b);
        case MathOp::kSinh: return std::sinh(a);
        case MathOp::kCosh: return std::cosh(a);
        case MathOp::kTanh: return std::tanh(a);
        case MathOp::kRadians: return a * (kPiF / 180.0f);
        case MathOp::kDegrees: return a * (180.0f / kPiF);
        case MathOp::kCount: break;
    }
    return 0.0f;
}

// The Clamp node: 'MINMAX' clamps to [lo, hi] as written, 'RANGE' to the range between them.
enum class ClampType : uint8_t { kMinMax, kRange, kCount };
constexpr const char* kClampTypeNames[] = {"MINMAX", "RANGE"};
inline float EvalClamp(ClampType type, float value, float lo, float hi) {
    if (type == ClampType::kRange && lo > hi) std::swap(lo, hi);
    return std::fmin(std::fmax(value, lo), hi);
}

// The Map Range node for floats (svm_node_map_range), its interpolations.
enum class MapRangeType : uint8_t { kLinear, kStepped, kSmoothstep, kSmootherstep, kCount };
constexpr const char* kMapRangeNames[] = {"LINEAR", "STEPPED", "SMOOTHSTEP", "SMOOTHERSTEP"};

inline float Smoothstep(float edge0, float edge1, float x) {
    if (x < edge0) return 0.0f;
    if (x >= edge1) return 1.0f;
    const float t = (x - edge0) / (edge1 - edge0);
    return (3.0f - 2.0f * t) * (t * t);
}
inline float Smootherstep(float edge0, float edge1, float x) {
    x = std::clamp(SafeDivide(x - edge0, edge1 - edge0), 0.0f, 1.0f);
    return x * x * x * (x * (x * 6.0f - 15.0f) + 10.0f);
}

// Cycles expands the node's Clamp option into a Clamp node of type 'RANGE' on the result (whatever the type).
inline float EvalMapRange(MapRangeType type, bool clamp, float value, float from_min, float from_max, float to_min,
                          float to_max, float steps) {
    if (from_max == from_min) return 0.0f;
    float factor = value;
    switch (type) {
        case MapRangeType::kStepped:
            factor = (value - from_min) / (from_max - from_min);
            factor = steps > 0.0f ? std::floor(factor * (steps + 1.0f)) / steps : 0.0f;
            break;
        case MapRangeType::kSmoothstep:
            factor = from_min > from_max ? 1.0f - Smoothstep(from_max, from_min, factor)
                                         : Smoothstep(from_min, from_max, factor);
            break;
        case MapRangeType::kSmootherstep:
            factor = from_min > from_max ? 1.0f - Smootherstep(from_max, from_min, factor)
                                         : Smootherstep(from_min, from_max, factor);
            break;
        default: factor = (value - from_min) / (from_max - from_min); break;
    }
    const float result = to_min + factor * (to_max - to_min);
    if (clamp) return EvalClamp(ClampType::kRange, result, to_min, to_max);
    return result;
}

}  // namespace sphrect::render::svm
