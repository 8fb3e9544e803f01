// Cycles 3.4's procedural texture nodes as pure functions (kernel/svm/{noise,fractal_noise,noisetex,musgrave,
// voronoi,white_noise,gradient,checker,wave,magic,brick}.h): the same hashes and Perlin noise, so that the same
// seed and point give Cycles' pattern.  Each node is one function of its settings (a small params struct: the
// node's enums and its input values, linked or not) and the point in texture space -- after the node's own
// Texture Mapping, which is the caller's.  No allocation, no state.
//
// Rounding: where Cycles' x86 kernels (SSE/AVX) evaluate in another order than its scalar code -- Perlin's fade
// and interpolations, 4D's w axis first -- this code follows the SIMD order.  It does not fuse multiply-adds as
// Cycles' AVX2 kernel does, so values differ from Cycles' in the last bits (~1e-7), which only matters exactly on
// a cell boundary (Voronoi, Checker, Brick), where Cycles' own hit points carry larger errors anyway.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>

#include "core/vec3.h"

namespace sphrect::render::svm {

// ---- Cycles' integer and float helpers (util/math.h) --------------------------------------------------------

// Cycles' float_to_int on x86 (cvttss2si): truncation, and INT_MIN for NaN and out-of-range values, which C++'s
// int(f) leaves undefined.  Huge coordinates go through here: they must give Cycles' lattice cell, not UB.
inline int FloatToInt(float f) {
    if (!(f > -2147483904.0f && f < 2147483648.0f)) return INT32_MIN;
    return int(f);
}
// floorf, bit for bit (-0 stays -0), without the libm call x86-64's baseline (no SSE4.1 round) makes of it.
[[gnu::always_inline]] inline float Floor(float x) {
    if (!(std::fabs(x) < 8388608.0f)) return x;  // 2^23: already an integer, or inf, or NaN
    const float t = float(int(x));
    return t > x ? t - 1.0f : (t == x ? x : t);
}
inline int FloorToInt(float f) { return FloatToInt(Floor(f)); }

inline uint32_t FloatBits(float f) {
    uint32_t u;
    std::memcpy(&u, &f, sizeof u);
    return u;
}

// Cycles' isfinite_safe / ensure_finite: written for fast math; with IEEE semantics std::isfinite is the same.
inline float EnsureFinite(float v) { return std::isfinite(v) ? v : 0.0f; }
// Cycles' clamp: min(max(a, lo), hi) with its comparisons, so NaN gives lo.  (Cycles' saturatef is Clamp(a, 0, 1);
// svm/color_nodes.h has its own Saturate.)
inline float Clamp(float a, float lo, float hi) {
    const float above = a > lo ? a : lo;
    return above < hi ? above : hi;
}
// Cycles' scalar mix (util/math.h): a + t (b - a).
inline float Mix(float a, float b, float t) { return a + t * (b - a); }
// Cycles' SSE mix (util/ssef.h), which its noise runs on x86: t b + (1 - t) a.
inline float MixSimd(float a, float b, float t) { return t * b + (1.0f - t) * a; }
inline float SmoothStep(float edge0, float edge1, float x) {
    if (x < edge0) return 0.0f;
    if (x >= edge1) return 1.0f;
    const float t = (x - edge0) / (edge1 - edge0);
    return (3.0f - 2.0f * t) * (t * t);
}

constexpr float kPi2 = 6.2831855f;      // Cycles' M_2PI_F
constexpr float kPiOver2 = 1.5707964f;  // M_PI_2_F

// ---- Hashes (util/hash.h): Bob Jenkins' lookup3 ----------------------------------------------------------------
// Always inlined: a noise evaluation hashes 2-16 corners, and a call per hash cost 4D noise ~30% of its time.

namespace detail {
inline uint32_t Rot(uint32_t x, int k) { return (x << k) | (x >> (32 - k)); }
[[gnu::always_inline]] inline void HashMix(uint32_t& a, uint32_t& b, uint32_t& c) {
    a -= c, a ^= Rot(c, 4), c += b;
    b -= a, b ^= Rot(a, 6), a += c;
    c -= b, c ^= Rot(b, 8), b += a;
    a -= c, a ^= Rot(c, 16), c += b;
    b -= a, b ^= Rot(a, 19), a += c;
    c -= b, c ^= Rot(b, 4), b += a;
}
[[gnu::always_inline]] inline void HashFinal(uint32_t& a, uint32_t& b, uint32_t& c) {
    c ^= b, c -= Rot(b, 14);
    a ^= c, a -= Rot(c, 11);
    b ^= a, b -= Rot(a, 25);
    c ^= b, c -= Rot(b, 16);
    a ^= c, a -= Rot(c, 4);
    b ^= a, b -= Rot(a, 14);
    c ^= b, c -= Rot(b, 24);
}
constexpr uint32_t HashInit(uint32_t n) { return 0xdeadbeefu + (n << 2) + 13u; }
}  // namespace detail

[[gnu::always_inline]] inline uint32_t HashUint(uint32_t kx) {
    uint32_t a = detail::HashInit(1), b = a, c = a;
    a += kx;
    detail::HashFinal(a, b, c);
    return c;
}
[[gnu::always_inline]] inline uint32_t HashUint2(uint32_t kx, uint32_t ky) {
    uint32_t a = detail::HashInit(2), b = a, c = a;
    b += ky;
    a += kx;
    detail::HashFinal(a, b, c);
    return c;
}
[[gnu::always_inline]] inline uint32_t HashUint3(uint32_t kx, uint32_t ky, uint32_t kz) {
    uint32_t a = detail::HashInit(3), b = a, c = a;
    c += kz;
    b += ky;
    a += kx;
    detail::HashFinal(a, b, c);
    return c;
}
[[gnu::always_inline]] inline uint32_t HashUint4(uint32_t kx, uint32_t ky, uint32_t kz, uint32_t kw) {
    uint32_t a = detail::HashInit(4), b = a, c = a;
    a += kx;
    b += ky;
    c += kz;
    detail::HashMix(a, b, c);
    a += kw;
    detail::HashFinal(a, b, c);
    return c;
}

// [0, 2^32 - 1] -> [0, 1], as Cycles' uint_to_float_incl (the float product, not a division).
inline float UintToFloatIncl(uint32_t n) { return float(n) * (1.0f / float(0xFFFFFFFFu)); }

// Floats hash by their bits: -0 and +0 differ, as in Cycles.
inline float HashFloatToFloat(float k) { return UintToFloatIncl(HashUint(FloatBits(k))); }
inline float HashFloat2ToFloat(float x, float y) { return UintToFloatIncl(HashUint2(FloatBits(x), FloatBits(y))); }
inline float HashFloat3ToFloat(float x, float y, float z) {
    return UintToFloatIncl(HashUint3(FloatBits(x), FloatBits(y), FloatBits(z)));
}
inline float HashFloat4ToFloat(float x, float y, float z, float w) {
    return UintToFloatIncl(HashUint4(FloatBits(x), FloatBits(y), FloatBits(z), FloatBits(w)));
}

// The float -> float3 hashes: a colour per point or cell (White Noise, Voronoi's Color).
inline Vec3f HashFloatToFloat3(float k) {
    return {HashFloatToFloat(k), HashFloat2ToFloat(k, 1.0f), HashFloat2ToFloat(k, 2.0f)};
}
inline Vec3f HashFloat2ToFloat3(float x, float y) {
    return {HashFloat2ToFloat(x, y), HashFloat3ToFloat(x, y, 1.0f), HashFloat3ToFloat(x, y, 2.0f)};
}
inline Vec3f HashFloat3ToFloat3(float x, float y, float z) {
    return {HashFloat3ToFloat(x, y, z), HashFloat4ToFloat(x, y, z, 1.0f), HashFloat4ToFloat(x, y, z, 2.0f)};
}
inline Vec3f HashFloat4ToFloat3(float x, float y, float z, float w) {
    return {HashFloat4ToFloat(x, y, z, w), HashFloat4ToFloat(z, x, w, y), HashFloat4ToFloat(w, z, y, x)};
}

// ---- Perlin noise (kernel/svm/noise.h) ------------------------------------------------------------------------

// Signed noise in about [-1, 1] (each dimension's OSL scale applied), 0 where Perlin noise is not finite.
float SignedNoise1(float x);
float SignedNoise2(float x, float y);
float SignedNoise3(float x, float y, float z);
float SignedNoise4(float x, float y, float z, float w);

// A point of 1 to 4 coordinates, what the dimension-generic code below works on.
template <int N>
struct TexVec {
    float v[N];
    float& operator[](int i) { return v[i]; }
    float operator[](int i) const { return v[i]; }
};

// Unsigned noise in [0, 1]: 0.5 snoise + 0.5.
template <int N>
float UnsignedNoise(const TexVec<N>& p);
template <int N>
float SignedNoise(const TexVec<N>& p);

// Cycles' fractal_noise_{1..4}d: octaves in [0, 15], the fraction blending in one more octave.
template <int N>
float FractalNoise(const TexVec<N>& p, float octaves, float roughness);

// ---- The nodes ------------------------------------------------------------------------------------------------

// The texture nodes, by the names the binding and the exporter use.
enum class ProceduralTexture : uint8_t {
    kNoise,
    kMusgrave,
    kVoronoi,
    kWhiteNoise,
    kGradient,
    kChecker,
    kWave,
    kMagic,
    kBrick
};
inline constexpr const char* kProceduralTextureNames[] = {"noise",   "musgrave", "voronoi", "white_noise", "gradient",
                                                          "checker", "wave",     "magic",   "brick"};
constexpr int kMaxMagicDepth = 10;  // Blender's limit of Turbulence Depth; deeper adds nothing in Cycles

// Enums in Blender's RNA order; their names, Blender's identifiers in lower case, are the binding's and the
// exporter's (procedural_params.py): one list each.

// Noise Texture
struct NoiseTextureParams {
    int dimensions = 3;  // 1..4: 1D reads w, 2D x y, 3D x y z, 4D x y z w
    float scale = 5.0f, detail = 2.0f, roughness = 0.5f, distortion = 0.0f;
};
struct NoiseTextureOutput {
    float fac = 0.0f;
    Vec3f color;
};
// `color_needed` false skips the two extra fractal sums of Color (Cycles skips them when Color is unlinked).
NoiseTextureOutput NoiseTexture(const NoiseTextureParams& params, Vec3f p, float w, bool color_needed = true);

// Musgrave Texture
enum class MusgraveType : uint8_t { kMultifractal, kRidgedMultifractal, kHybridMultifractal, kFbm, kHeteroTerrain };
inline constexpr const char* kMusgraveTypeNames[] = {"multifractal", "ridged_multifractal", "hybrid_multifractal",
                                                     "fbm", "hetero_terrain"};
struct MusgraveTextureParams {
    int dimensions = 3;
    MusgraveType type = MusgraveType::kFbm;
    float scale = 5.0f, detail = 2.0f, dimension = 2.0f, lacunarity = 2.0f, offset = 0.0f, gain = 1.0f;
};
float MusgraveTexture(const MusgraveTextureParams& params, Vec3f p, float w);

// Voronoi Texture
enum class VoronoiFeature : uint8_t { kF1, kF2, kSmoothF1, kDistanceToEdge, kNSphereRadius };
inline constexpr const char* kVoronoiFeatureNames[] = {"f1", "f2", "smooth_f1", "distance_to_edge", "n_sphere_radius"};
enum class VoronoiMetric : uint8_t { kEuclidean, kManhattan, kChebychev, kMinkowski };
inline constexpr const char* kVoronoiMetricNames[] = {"euclidean", "manhattan", "chebychev", "minkowski"};
struct VoronoiTextureParams {
    int dimensions = 3;
    VoronoiFeature feature = VoronoiFeature::kF1;
    VoronoiMetric metric = VoronoiMetric::kEuclidean;
    float scale = 5.0f, smoothness = 1.0f, exponent = 0.5f, randomness = 1.0f;
};
struct VoronoiTextureOutput {
    float distance = 0.0f;
    Vec3f color;
    Vec3f position;
    float w = 0.0f;
    float radius = 0.0f;
};
VoronoiTextureOutput VoronoiTexture(const VoronoiTextureParams& params, Vec3f p, float w);

// White Noise Texture (no scale: the point's bits are the seed)
struct WhiteNoiseTextureParams {
    int dimensions = 3;
};
struct WhiteNoiseTextureOutput {
    float value = 0.0f;
    Vec3f color;
};
WhiteNoiseTextureOutput WhiteNoiseTexture(const WhiteNoiseTextureParams& params, Vec3f p, float w);

// Gradient Texture (Color is (fac, fac, fac))
enum class GradientType : uint8_t { kLinear, kQuadratic, kEasing, kDiagonal, kSpherical, kQuadraticSphere, kRadial };
inline constexpr const char* kGradientTypeNames[] = {"linear",    "quadratic",        "easing", "diagonal",
                                                     "spherical", "quadratic_sphere", "radial"};
struct GradientTextureParams {
    GradientType type = GradientType::kLinear;
};
float GradientTexture(const GradientTextureParams& params, Vec3f p);

// Checker Texture
struct CheckerTextureParams {
    Vec3f color1{0.8f, 0.8f, 0.8f}, color2{0.2f, 0.2f, 0.2f};
    float scale = 5.0f;
};
struct ColorFacOutput {
    Vec3f color;
    float fac = 0.0f;
};
ColorFacOutput CheckerTexture(const CheckerTextureParams& params, Vec3f p);

// Wave Texture (Color is (fac, fac, fac))
enum class WaveType : uint8_t { kBands, kRings };
inline constexpr const char* kWaveTypeNames[] = {"bands", "rings"};
enum class WaveBandsDirection : uint8_t { kX, kY, kZ, kDiagonal };
inline constexpr const char* kWaveBandsDirectionNames[] = {"x", "y", "z", "diagonal"};
enum class WaveRingsDirection : uint8_t { kX, kY, kZ, kSpherical };
inline constexpr const char* kWaveRingsDirectionNames[] = {"x", "y", "z", "spherical"};
enum class WaveProfile : uint8_t { kSin, kSaw, kTri };
inline constexpr const char* kWaveProfileNames[] = {"sin", "saw", "tri"};
struct WaveTextureParams {
    WaveType type = WaveType::kBands;
    WaveBandsDirection bands_direction = WaveBandsDirection::kX;
    WaveRingsDirection rings_direction = WaveRingsDirection::kX;
    WaveProfile profile = WaveProfile::kSin;
    float scale = 5.0f, distortion = 0.0f, detail = 2.0f, detail_scale = 1.0f, detail_roughness = 0.5f,
          phase_offset = 0.0f;
};
float WaveTexture(const WaveTextureParams& params, Vec3f p);

// Magic Texture
struct MagicTextureParams {
    int depth = 2;  // Blender's Turbulence Depth, 0..10
    float scale = 5.0f, distortion = 1.0f;
};
ColorFacOutput MagicTexture(const MagicTextureParams& params, Vec3f p);

// Brick Texture
struct BrickTextureParams {
    float offset = 0.5f;
    int offset_frequency = 2;
    float squash = 1.0f;
    int squash_frequency = 2;
    Vec3f color1{0.8f, 0.8f, 0.8f}, color2{0.2f, 0.2f, 0.2f}, mortar{0.0f, 0.0f, 0.0f};
    float scale = 5.0f, mortar_size = 0.02f, mortar_smooth = 0.1f, bias = 0.0f, brick_width = 0.5f, row_height = 0.25f;
};
ColorFacOutput BrickTexture(const BrickTextureParams& params, Vec3f p);

}  // namespace sphrect::render::svm
