// Cycles 3.4's procedural textures: see procedural_textures.h.  Formulas and constants are Cycles'
// (kernel/svm/*.h); the dimension-generic code runs each node's 1D..4D variants through one template, in the
// same loop order (x fastest) and the same float operation order as Cycles' x86 build.
#include "render/svm/procedural_textures.h"

#include <algorithm>

namespace sphrect::render::svm {

namespace {

// ---- Small vector arithmetic on TexVec<N> ----------------------------------------------------------------------

template <int N>
TexVec<N> operator+(TexVec<N> a, const TexVec<N>& b) {
    for (int i = 0; i < N; ++i) a[i] += b[i];
    return a;
}
template <int N>
TexVec<N> operator-(TexVec<N> a, const TexVec<N>& b) {
    for (int i = 0; i < N; ++i) a[i] -= b[i];
    return a;
}
template <int N>
TexVec<N> operator*(TexVec<N> a, float s) {
    for (int i = 0; i < N; ++i) a[i] *= s;
    return a;
}
template <int N>
TexVec<N> FloorVec(TexVec<N> a) {
    for (int i = 0; i < N; ++i) a[i] = Floor(a[i]);
    return a;
}
template <int N>
TexVec<N> Splat(float s) {
    TexVec<N> a;
    for (int i = 0; i < N; ++i) a[i] = s;
    return a;
}
// Cycles' vector / scalar: float2 and float4 multiply by the reciprocal, float3 (SSE) divides.
template <int N>
TexVec<N> DivideByScalar(TexVec<N> a, float s) {
    if (N == 2 || N == 4) return a * (1.0f / s);
    for (int i = 0; i < N; ++i) a[i] /= s;
    return a;
}
// Cycles' dot: float2/float3 summed in order, float4 in pairs (as _mm_dp_ps adds).
template <int N>
[[gnu::always_inline]] inline float Dot(const TexVec<N>& a, const TexVec<N>& b) {
    if constexpr (N == 4) return (a[0] * b[0] + a[1] * b[1]) + (a[2] * b[2] + a[3] * b[3]);
    float s = a[0] * b[0];
    for (int i = 1; i < N; ++i) s += a[i] * b[i];
    return s;
}
template <int N>
[[gnu::always_inline]] inline float Length(const TexVec<N>& a) {
    if constexpr (N == 1) return std::fabs(a[0]);
    return std::sqrt(Dot(a, a));
}
template <int N>
TexVec<N> Normalize(const TexVec<N>& a) {
    return DivideByScalar(a, Length(a));
}

Vec3f MixColor(const Vec3f& a, const Vec3f& b, float t) { return a + (b - a) * t; }

TexVec<1> Vec1(float x) { return {{x}}; }

// ---- Perlin noise --------------------------------------------------------------------------------------------

float FadeScalar(float t) { return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f); }
// The SSE fade (madd order): (t t) (t (t (6 t - 15) + 10)).
[[gnu::always_inline]] inline float FadeSimd(float t) {
    const float a = t * 6.0f + -15.0f;
    const float b = t * a + 10.0f;
    return (t * t) * (t * b);
}
// Gradients without branches: the hash's bits are random, so branching on them mispredicts about half the time
// (4D noise spent 90% of its time there).  Negation flips the sign bit, as Cycles' SIMD negate_if_nth_bit.
[[gnu::always_inline]] inline float BitsFloat(uint32_t u) {
    float f;
    std::memcpy(&f, &u, sizeof f);
    return f;
}
[[gnu::always_inline]] inline float NegateIfBit(float v, uint32_t h, int bit) {
    return BitsFloat(FloatBits(v) ^ (((h >> bit) & 1u) << 31));
}
[[gnu::always_inline]] inline float Select(bool condition, float a, float b) {
    const uint32_t mask = 0u - uint32_t(condition);
    return BitsFloat((FloatBits(a) & mask) | (FloatBits(b) & ~mask));
}

[[gnu::always_inline]] inline float Grad1(uint32_t hash, float x) {
    const uint32_t h = hash & 15;
    const float g = float(1 + (h & 7));
    return NegateIfBit(g, h, 3) * x;
}
[[gnu::always_inline]] inline float Grad2(uint32_t hash, float x, float y) {
    const uint32_t h = hash & 7;
    const float u = Select(h < 4, x, y);
    const float v = 2.0f * Select(h < 4, y, x);
    return NegateIfBit(u, h, 0) + NegateIfBit(v, h, 1);
}
[[gnu::always_inline]] inline float Grad3(uint32_t hash, float x, float y, float z) {
    const uint32_t h = hash & 15;
    const float u = Select(h < 8, x, y);
    const float vt = Select(h == 12 || h == 14, x, z);
    const float v = Select(h < 4, y, vt);
    return NegateIfBit(u, h, 0) + NegateIfBit(v, h, 1);
}
[[gnu::always_inline]] inline float Grad4(uint32_t hash, float x, float y, float z, float w) {
    const uint32_t h = hash & 31;
    const float u = Select(h < 24, x, y);
    const float v = Select(h < 16, y, z);
    const float s = Select(h < 8, z, w);
    return NegateIfBit(u, h, 0) + NegateIfBit(v, h, 1) + NegateIfBit(s, h, 2);
}

// floorfrac: the lattice cell (as Cycles' truncation of the floor) and the fraction in it.  Cells are hashed as
// unsigned, so cell + 1 wraps where Cycles' SIMD integers wrap.
float FloorFrac(float x, uint32_t* cell) {
    const float f = Floor(x);
    *cell = uint32_t(FloatToInt(f));
    return x - f;
}

float Perlin1(float x) {
    uint32_t X;
    const float fx = FloorFrac(x, &X);
    const float u = FadeScalar(fx);  // 1D noise is scalar code in Cycles
    return Mix(Grad1(HashUint(X), fx), Grad1(HashUint(X + 1), fx - 1.0f), u);
}

float Perlin2(float x, float y) {
    uint32_t X, Y;
    const float fx = FloorFrac(x, &X), fy = FloorFrac(y, &Y);
    const float u = FadeSimd(fx), v = FadeSimd(fy);
    const float g0 = MixSimd(Grad2(HashUint2(X, Y), fx, fy), Grad2(HashUint2(X + 1, Y), fx - 1.0f, fy), u);
    const float g1 =
        MixSimd(Grad2(HashUint2(X, Y + 1), fx, fy - 1.0f), Grad2(HashUint2(X + 1, Y + 1), fx - 1.0f, fy - 1.0f), u);
    return MixSimd(g0, g1, v);
}

// Trilinear interpolation of corner values c[dx][dy][dz] as Cycles' SIMD tri_mix: x, then y, then z.
[[gnu::always_inline]] inline float TriMixSimd(const float c[2][2][2], float u, float v, float w) {
    float s[2][2];
    for (int dy = 0; dy < 2; ++dy)
        for (int dz = 0; dz < 2; ++dz) s[dy][dz] = MixSimd(c[0][dy][dz], c[1][dy][dz], u);
    return MixSimd(MixSimd(s[0][0], s[1][0], v), MixSimd(s[0][1], s[1][1], v), w);
}

float Perlin3(float x, float y, float z) {
    uint32_t X, Y, Z;
    const float fx = FloorFrac(x, &X), fy = FloorFrac(y, &Y), fz = FloorFrac(z, &Z);
    float c[2][2][2];
    for (uint32_t dx = 0; dx < 2; ++dx)
        for (uint32_t dy = 0; dy < 2; ++dy)
            for (uint32_t dz = 0; dz < 2; ++dz)
                c[dx][dy][dz] =
                    Grad3(HashUint3(X + dx, Y + dy, Z + dz), fx - float(dx), fy - float(dy), fz - float(dz));
    return TriMixSimd(c, FadeSimd(fx), FadeSimd(fy), FadeSimd(fz));
}

// Cycles' AVX quad_mix: first along w, then trilinear in x, y, z.
float Perlin4(float x, float y, float z, float w) {
    uint32_t X, Y, Z, W;
    const float fx = FloorFrac(x, &X), fy = FloorFrac(y, &Y), fz = FloorFrac(z, &Z), fw = FloorFrac(w, &W);
    const float s = FadeSimd(fw);
    float c[2][2][2];
    for (uint32_t dx = 0; dx < 2; ++dx)
        for (uint32_t dy = 0; dy < 2; ++dy)
            for (uint32_t dz = 0; dz < 2; ++dz) {
                const float gx = fx - float(dx), gy = fy - float(dy), gz = fz - float(dz);
                const float g0 = Grad4(HashUint4(X + dx, Y + dy, Z + dz, W), gx, gy, gz, fw);
                const float g1 = Grad4(HashUint4(X + dx, Y + dy, Z + dz, W + 1), gx, gy, gz, fw - 1.0f);
                c[dx][dy][dz] = MixSimd(g0, g1, s);
            }
    return TriMixSimd(c, FadeSimd(fx), FadeSimd(fy), FadeSimd(fz));
}

// ---- Seeds as offsets (noisetex.h): components in [100, 200] ---------------------------------------------------

template <int N>
TexVec<N> RandomOffset(float seed) {
    TexVec<N> o;
    if constexpr (N == 1) {
        o[0] = 100.0f + HashFloatToFloat(seed) * 100.0f;
    } else {
        for (int i = 0; i < N; ++i) o[i] = 100.0f + HashFloat2ToFloat(seed, float(i)) * 100.0f;
    }
    return o;
}

}  // namespace

float SignedNoise1(float x) { return 0.2500f * EnsureFinite(Perlin1(x)); }
float SignedNoise2(float x, float y) { return 0.6616f * EnsureFinite(Perlin2(x, y)); }
float SignedNoise3(float x, float y, float z) { return 0.9820f * EnsureFinite(Perlin3(x, y, z)); }
float SignedNoise4(float x, float y, float z, float w) { return 0.8344f * EnsureFinite(Perlin4(x, y, z, w)); }

template <int N>
float SignedNoise(const TexVec<N>& p) {
    if constexpr (N == 1) {
        return SignedNoise1(p[0]);
    } else if constexpr (N == 2) {
        return SignedNoise2(p[0], p[1]);
    } else if constexpr (N == 3) {
        return SignedNoise3(p[0], p[1], p[2]);
    } else {
        return SignedNoise4(p[0], p[1], p[2], p[3]);
    }
}
template <int N>
float UnsignedNoise(const TexVec<N>& p) {
    return 0.5f * SignedNoise(p) + 0.5f;
}

template <int N>
float FractalNoise(const TexVec<N>& p, float octaves, float roughness) {
    float fscale = 1.0f, amp = 1.0f, maxamp = 0.0f, sum = 0.0f;
    octaves = Clamp(octaves, 0.0f, 15.0f);
    const int n = FloatToInt(octaves);
    for (int i = 0; i <= n; ++i) {
        const float t = UnsignedNoise(p * fscale);
        sum += t * amp;
        maxamp += amp;
        amp *= Clamp(roughness, 0.0f, 1.0f);
        fscale *= 2.0f;
    }
    const float rmd = octaves - Floor(octaves);
    if (rmd == 0.0f) return sum / maxamp;
    // The fractional octave: blend the normalised sums without and with one more octave.
    const float t = UnsignedNoise(p * fscale);
    const float sum2 = (sum + t * amp) / (maxamp + amp);
    return (1.0f - rmd) * (sum / maxamp) + rmd * sum2;
}

template float SignedNoise<1>(const TexVec<1>&);
template float SignedNoise<2>(const TexVec<2>&);
template float SignedNoise<3>(const TexVec<3>&);
template float SignedNoise<4>(const TexVec<4>&);
template float UnsignedNoise<1>(const TexVec<1>&);
template float UnsignedNoise<2>(const TexVec<2>&);
template float UnsignedNoise<3>(const TexVec<3>&);
template float UnsignedNoise<4>(const TexVec<4>&);
template float FractalNoise<1>(const TexVec<1>&, float, float);
template float FractalNoise<2>(const TexVec<2>&, float, float);
template float FractalNoise<3>(const TexVec<3>&, float, float);
template float FractalNoise<4>(const TexVec<4>&, float, float);

namespace {

// The node's point as N coordinates: 1D is w, 2D x y, 3D x y z, 4D x y z w.
template <int N>
TexVec<N> NodePoint(const Vec3f& p, float w) {
    if constexpr (N == 1) return {{w}};
    if constexpr (N == 2) return {{p.x, p.y}};
    if constexpr (N == 3) return {{p.x, p.y, p.z}};
    if constexpr (N == 4) return {{p.x, p.y, p.z, w}};
}

// ---- Noise Texture (noisetex.h) ----------------------------------------------------------------------------------

template <int N>
NoiseTextureOutput NoiseTextureN(const NoiseTextureParams& params, TexVec<N> p, bool color_needed) {
    // Distortion displaces the point by signed noise seeded by offsets 0..N-1; Color's green and blue are
    // fractal sums seeded by the next two offsets.
    if (params.distortion != 0.0f) {
        TexVec<N> d;
        for (int i = 0; i < N; ++i) d[i] = SignedNoise(p + RandomOffset<N>(float(i))) * params.distortion;
        p = p + d;
    }
    NoiseTextureOutput out;
    out.fac = FractalNoise(p, params.detail, params.roughness);
    if (color_needed) {
        const float seed = float(N);
        out.color = {out.fac, FractalNoise(p + RandomOffset<N>(seed), params.detail, params.roughness),
                     FractalNoise(p + RandomOffset<N>(seed + 1.0f), params.detail, params.roughness)};
    }
    return out;
}

// ---- Musgrave Texture (musgrave.h; "Texturing and Modeling: A Procedural Approach") ---------------------------

template <int N>
float MusgraveFbm(TexVec<N> p, float H, float lacunarity, float octaves) {
    float value = 0.0f, pwr = 1.0f;
    const float pwHL = std::pow(lacunarity, -H);
    for (int i = 0; i < FloatToInt(octaves); ++i) {
        value += SignedNoise(p) * pwr;
        pwr *= pwHL;
        p = p * lacunarity;
    }
    const float rmd = octaves - Floor(octaves);
    if (rmd != 0.0f) value += rmd * SignedNoise(p) * pwr;
    return value;
}

template <int N>
float MusgraveMultifractal(TexVec<N> p, float H, float lacunarity, float octaves) {
    float value = 1.0f, pwr = 1.0f;
    const float pwHL = std::pow(lacunarity, -H);
    for (int i = 0; i < FloatToInt(octaves); ++i) {
        value *= (pwr * SignedNoise(p) + 1.0f);
        pwr *= pwHL;
        p = p * lacunarity;
    }
    const float rmd = octaves - Floor(octaves);
    if (rmd != 0.0f) value *= (rmd * pwr * SignedNoise(p) + 1.0f);
    return value;
}

template <int N>
float MusgraveHeteroTerrain(TexVec<N> p, float H, float lacunarity, float octaves, float offset) {
    const float pwHL = std::pow(lacunarity, -H);
    float pwr = pwHL;
    float value = offset + SignedNoise(p);  // the first octave unscaled
    p = p * lacunarity;
    for (int i = 1; i < FloatToInt(octaves); ++i) {
        const float increment = (SignedNoise(p) + offset) * pwr * value;
        value += increment;
        pwr *= pwHL;
        p = p * lacunarity;
    }
    const float rmd = octaves - Floor(octaves);
    if (rmd != 0.0f) {
        const float increment = (SignedNoise(p) + offset) * pwr * value;
        value += rmd * increment;
    }
    return value;
}

template <int N>
float MusgraveHybridMultifractal(TexVec<N> p, float H, float lacunarity, float octaves, float offset, float gain) {
    const float pwHL = std::pow(lacunarity, -H);
    float pwr = 1.0f, value = 0.0f, weight = 1.0f;
    for (int i = 0; weight > 0.001f && i < FloatToInt(octaves); ++i) {
        if (weight > 1.0f) weight = 1.0f;
        const float signal = (SignedNoise(p) + offset) * pwr;
        pwr *= pwHL;
        value += weight * signal;
        weight *= gain * signal;
        p = p * lacunarity;
    }
    const float rmd = octaves - Floor(octaves);
    if (rmd != 0.0f && weight > 0.001f) {
        if (weight > 1.0f) weight = 1.0f;
        const float signal = (SignedNoise(p) + offset) * pwr;
        value += rmd * weight * signal;
    }
    return value;
}

// Ridged: no fractional octave in Cycles (the detail's fraction is ignored).
template <int N>
float MusgraveRidgedMultifractal(TexVec<N> p, float H, float lacunarity, float octaves, float offset, float gain) {
    const float pwHL = std::pow(lacunarity, -H);
    float pwr = pwHL;
    float signal = offset - std::fabs(SignedNoise(p));
    signal *= signal;
    float value = signal, weight = 1.0f;
    for (int i = 1; i < FloatToInt(octaves); ++i) {
        p = p * lacunarity;
        weight = Clamp(signal * gain, 0.0f, 1.0f);
        signal = offset - std::fabs(SignedNoise(p));
        signal *= signal;
        signal *= weight;
        value += signal * pwr;
        pwr *= pwHL;
    }
    return value;
}

template <int N>
float MusgraveN(const MusgraveTextureParams& params, const TexVec<N>& p) {
    const float dimension = std::fmax(params.dimension, 1e-5f);
    const float detail = Clamp(params.detail, 0.0f, 15.0f);
    const float lacunarity = std::fmax(params.lacunarity, 1e-5f);
    switch (params.type) {
        case MusgraveType::kMultifractal: return MusgraveMultifractal(p, dimension, lacunarity, detail);
        case MusgraveType::kFbm: return MusgraveFbm(p, dimension, lacunarity, detail);
        case MusgraveType::kHybridMultifractal:
            return MusgraveHybridMultifractal(p, dimension, lacunarity, detail, params.offset, params.gain);
        case MusgraveType::kRidgedMultifractal:
            return MusgraveRidgedMultifractal(p, dimension, lacunarity, detail, params.offset, params.gain);
        case MusgraveType::kHeteroTerrain:
            return MusgraveHeteroTerrain(p, dimension, lacunarity, detail, params.offset);
    }
    return 0.0f;
}

// ---- Voronoi Texture (voronoi.h; after Inigo Quilez) -----------------------------------------------------------

// A cell's feature point in [0, 1)^N (hash_floatN_to_floatN).
template <int N>
[[gnu::always_inline]] inline TexVec<N> HashToPoint(const TexVec<N>& c) {
    if constexpr (N == 1) return {{HashFloatToFloat(c[0])}};
    if constexpr (N == 2) return {{HashFloat2ToFloat(c[0], c[1]), HashFloat3ToFloat(c[0], c[1], 1.0f)}};
    if constexpr (N == 3) {
        const Vec3f h = HashFloat3ToFloat3(c[0], c[1], c[2]);
        return {{h.x, h.y, h.z}};
    }
    if constexpr (N == 4)
        return {{HashFloat4ToFloat(c[0], c[1], c[2], c[3]), HashFloat4ToFloat(c[3], c[0], c[1], c[2]),
                 HashFloat4ToFloat(c[2], c[3], c[0], c[1]), HashFloat4ToFloat(c[1], c[2], c[3], c[0])}};
}
// A cell's colour (hash_floatN_to_float3).
template <int N>
[[gnu::always_inline]] inline Vec3f HashToColor(const TexVec<N>& c) {
    if constexpr (N == 1) return HashFloatToFloat3(c[0]);
    if constexpr (N == 2) return HashFloat2ToFloat3(c[0], c[1]);
    if constexpr (N == 3) return HashFloat3ToFloat3(c[0], c[1], c[2]);
    if constexpr (N == 4) return HashFloat4ToFloat3(c[0], c[1], c[2], c[3]);
}

// Distance of a to b under the metric (1D: always |b - a|).
template <int N>
[[gnu::always_inline]] inline float VoronoiDistance(const TexVec<N>& a, const TexVec<N>& b, VoronoiMetric metric,
                                                    float exponent) {
    if constexpr (N == 1) return std::fabs(b[0] - a[0]);
    switch (metric) {
        case VoronoiMetric::kEuclidean: return Length(a - b);
        case VoronoiMetric::kManhattan: {
            float s = std::fabs(a[0] - b[0]);
            for (int i = 1; i < N; ++i) s += std::fabs(a[i] - b[i]);
            return s;
        }
        case VoronoiMetric::kChebychev: {
            float m = std::fabs(a[N - 1] - b[N - 1]);  // max(|x|, max(|y|, ...)): innermost last
            for (int i = N - 2; i >= 0; --i) m = std::max(std::fabs(a[i] - b[i]), m);
            return m;
        }
        case VoronoiMetric::kMinkowski: {
            float s = std::pow(std::fabs(a[0] - b[0]), exponent);
            for (int i = 1; i < N; ++i) s += std::pow(std::fabs(a[i] - b[i]), exponent);
            return std::pow(s, 1.0f / exponent);
        }
    }
    return 0.0f;
}

// Calls f(offset) for every cell offset in [-r, r]^N, x fastest (Cycles' loop nest).
template <int N, class F>
void ForEachCellOffset(int r, F&& f) {
    int idx[N];
    for (int i = 0; i < N; ++i) idx[i] = -r;
    for (;;) {
        TexVec<N> o;
        for (int i = 0; i < N; ++i) o[i] = float(idx[i]);
        f(o);
        int d = 0;
        while (d < N && idx[d] == r) idx[d++] = -r;
        if (d == N) return;
        ++idx[d];
    }
}

template <int N>
struct VoronoiResult {
    float distance = 0.0f;
    Vec3f color;
    TexVec<N> position = Splat<N>(0.0f);
};

template <int N>
VoronoiResult<N> VoronoiF1(const TexVec<N>& coord, float exponent, float randomness, VoronoiMetric metric) {
    const TexVec<N> cell = FloorVec(coord), local = coord - cell;
    float min_distance = 8.0f;
    TexVec<N> target_offset = Splat<N>(0.0f), target_position = Splat<N>(0.0f);
    ForEachCellOffset<N>(1, [&](const TexVec<N>& offset) {
        const TexVec<N> point = offset + HashToPoint(cell + offset) * randomness;
        const float d = VoronoiDistance(point, local, metric, exponent);
        if (d < min_distance) {
            target_offset = offset;
            min_distance = d;
            target_position = point;
        }
    });
    return {min_distance, HashToColor(cell + target_offset), target_position + cell};
}

// Smooth F1: a smooth minimum over a 5^N neighbourhood (Quilez's smooth Voronoi); colour and position blend alike.
template <int N>
VoronoiResult<N> VoronoiSmoothF1(const TexVec<N>& coord, float smoothness, float exponent, float randomness,
                                 VoronoiMetric metric) {
    const TexVec<N> cell = FloorVec(coord), local = coord - cell;
    float smooth_distance = 8.0f;
    Vec3f smooth_color{0.0f, 0.0f, 0.0f};
    TexVec<N> smooth_position = Splat<N>(0.0f);
    ForEachCellOffset<N>(2, [&](const TexVec<N>& offset) {
        const TexVec<N> point = offset + HashToPoint(cell + offset) * randomness;
        const float d = VoronoiDistance(point, local, metric, exponent);
        const float h = SmoothStep(0.0f, 1.0f, 0.5f + 0.5f * (smooth_distance - d) / smoothness);
        float correction = smoothness * h * (1.0f - h);
        smooth_distance = Mix(smooth_distance, d, h) - correction;
        correction /= 1.0f + 3.0f * smoothness;
        const Vec3f cell_color = HashToColor(cell + offset);
        smooth_color = MixColor(smooth_color, cell_color, h) - Vec3f(correction, correction, correction);
        for (int i = 0; i < N; ++i) smooth_position[i] = Mix(smooth_position[i], point[i], h) - correction;
    });
    return {smooth_distance, smooth_color, cell + smooth_position};
}

template <int N>
VoronoiResult<N> VoronoiF2(const TexVec<N>& coord, float exponent, float randomness, VoronoiMetric metric) {
    const TexVec<N> cell = FloorVec(coord), local = coord - cell;
    float distance_f1 = 8.0f, distance_f2 = 8.0f;
    TexVec<N> offset_f1 = Splat<N>(0.0f), position_f1 = Splat<N>(0.0f);
    TexVec<N> offset_f2 = Splat<N>(0.0f), position_f2 = Splat<N>(0.0f);
    ForEachCellOffset<N>(1, [&](const TexVec<N>& offset) {
        const TexVec<N> point = offset + HashToPoint(cell + offset) * randomness;
        const float d = VoronoiDistance(point, local, metric, exponent);
        if (d < distance_f1) {
            distance_f2 = distance_f1;
            distance_f1 = d;
            offset_f2 = offset_f1;
            offset_f1 = offset;
            position_f2 = position_f1;
            position_f1 = point;
        } else if (d < distance_f2) {
            distance_f2 = d;
            offset_f2 = offset;
            position_f2 = point;
        }
    });
    return {distance_f2, HashToColor(cell + offset_f2), position_f2 + cell};
}

// Distance to the nearest Voronoi edge: 1D between the neighbouring midpoints, else the smallest distance to the
// bisectors of the closest point and each other point (Quilez), always Euclidean.
template <int N>
float VoronoiDistanceToEdge(const TexVec<N>& coord, float randomness) {
    const TexVec<N> cell = FloorVec(coord), local = coord - cell;
    if constexpr (N == 1) {
        const float c = cell[0], x = local[0];
        const float mid = HashFloatToFloat(c) * randomness;
        const float left = -1.0f + HashFloatToFloat(c - 1.0f) * randomness;
        const float right = 1.0f + HashFloatToFloat(c + 1.0f) * randomness;
        return std::min(std::fabs((mid + left) / 2.0f - x), std::fabs((mid + right) / 2.0f - x));
    } else {
        TexVec<N> to_closest = Splat<N>(0.0f);
        float min_distance = 8.0f;
        ForEachCellOffset<N>(1, [&](const TexVec<N>& offset) {
            const TexVec<N> to_point = offset + HashToPoint(cell + offset) * randomness - local;
            const float d = Dot(to_point, to_point);
            if (d < min_distance) {
                min_distance = d;
                to_closest = to_point;
            }
        });
        min_distance = 8.0f;
        ForEachCellOffset<N>(1, [&](const TexVec<N>& offset) {
            const TexVec<N> to_point = offset + HashToPoint(cell + offset) * randomness - local;
            const TexVec<N> perpendicular = to_point - to_closest;
            if (Dot(perpendicular, perpendicular) > 0.0001f) {
                const float d = Dot(DivideByScalar(to_closest + to_point, 2.0f), Normalize(perpendicular));
                min_distance = std::min(min_distance, d);
            }
        });
        return min_distance;
    }
}

// Half the distance from the closest point to its own closest point: the radius of spheres packed in the cells.
template <int N>
float VoronoiNSphereRadius(const TexVec<N>& coord, float randomness) {
    const TexVec<N> cell = FloorVec(coord), local = coord - cell;
    TexVec<N> closest = Splat<N>(0.0f), closest_offset = Splat<N>(0.0f);
    float min_distance = 8.0f;
    ForEachCellOffset<N>(1, [&](const TexVec<N>& offset) {
        const TexVec<N> point = offset + HashToPoint(cell + offset) * randomness;
        const float d = Length(point - local);
        if (d < min_distance) {
            min_distance = d;
            closest = point;
            closest_offset = offset;
        }
    });
    min_distance = 8.0f;
    TexVec<N> closest_to_closest = Splat<N>(0.0f);
    ForEachCellOffset<N>(1, [&](const TexVec<N>& o) {
        bool center = true;
        for (int i = 0; i < N; ++i) center = center && o[i] == 0.0f;
        if (center) return;
        const TexVec<N> offset = o + closest_offset;
        const TexVec<N> point = offset + HashToPoint(cell + offset) * randomness;
        const float d = Length(closest - point);
        if (d < min_distance) {
            min_distance = d;
            closest_to_closest = point;
        }
    });
    return Length(closest_to_closest - closest) / 2.0f;
}

template <int N>
VoronoiTextureOutput VoronoiN(const VoronoiTextureParams& params, const Vec3f& p, float w) {
    const float randomness = Clamp(params.randomness, 0.0f, 1.0f);
    const float smoothness = Clamp(params.smoothness / 2.0f, 0.0f, 0.5f);
    const float scale = params.scale;
    const TexVec<N> coord = NodePoint<N>(p * scale, w * scale);
    VoronoiTextureOutput out;
    VoronoiResult<N> r;
    switch (params.feature) {
        case VoronoiFeature::kF1: r = VoronoiF1(coord, params.exponent, randomness, params.metric); break;
        case VoronoiFeature::kSmoothF1:
            r = VoronoiSmoothF1(coord, smoothness, params.exponent, randomness, params.metric);
            break;
        case VoronoiFeature::kF2: r = VoronoiF2(coord, params.exponent, randomness, params.metric); break;
        case VoronoiFeature::kDistanceToEdge: r.distance = VoronoiDistanceToEdge(coord, randomness); break;
        case VoronoiFeature::kNSphereRadius: out.radius = VoronoiNSphereRadius(coord, randomness); break;
    }
    out.distance = r.distance;
    out.color = r.color;
    // Position and W back in the node's input space (0 for scale 0, as Cycles' safe_divide).
    const TexVec<N> position = scale != 0.0f ? DivideByScalar(r.position, scale) : Splat<N>(0.0f);
    if constexpr (N == 1) out.w = scale != 0.0f ? r.position[0] / scale : 0.0f;
    if constexpr (N == 2) out.position = {position[0], position[1], 0.0f};
    if constexpr (N == 3) out.position = {position[0], position[1], position[2]};
    if constexpr (N == 4) {
        out.position = {position[0], position[1], position[2]};
        out.w = position[3];
    }
    return out;
}

}  // namespace

// ---- The nodes' entry points ------------------------------------------------------------------------------------

NoiseTextureOutput NoiseTexture(const NoiseTextureParams& params, Vec3f p, float w, bool color_needed) {
    p *= params.scale;
    w *= params.scale;
    switch (params.dimensions) {
        case 1: return NoiseTextureN<1>(params, NodePoint<1>(p, w), color_needed);
        case 2: return NoiseTextureN<2>(params, NodePoint<2>(p, w), color_needed);
        case 3: return NoiseTextureN<3>(params, NodePoint<3>(p, w), color_needed);
        default: return NoiseTextureN<4>(params, NodePoint<4>(p, w), color_needed);
    }
}

float MusgraveTexture(const MusgraveTextureParams& params, Vec3f p, float w) {
    const float s = params.scale;
    switch (params.dimensions) {
        case 1: return MusgraveN<1>(params, Vec1(w * s));
        case 2: return MusgraveN<2>(params, TexVec<2>{{p.x * s, p.y * s}});
        case 3: return MusgraveN<3>(params, TexVec<3>{{p.x * s, p.y * s, p.z * s}});
        default: return MusgraveN<4>(params, TexVec<4>{{p.x * s, p.y * s, p.z * s, w * s}});
    }
}

VoronoiTextureOutput VoronoiTexture(const VoronoiTextureParams& params, Vec3f p, float w) {
    switch (params.dimensions) {
        case 1: return VoronoiN<1>(params, p, w);
        case 2: return VoronoiN<2>(params, p, w);
        case 3: return VoronoiN<3>(params, p, w);
        default: return VoronoiN<4>(params, p, w);
    }
}

WhiteNoiseTextureOutput WhiteNoiseTexture(const WhiteNoiseTextureParams& params, Vec3f p, float w) {
    switch (params.dimensions) {
        case 1: return {HashFloatToFloat(w), HashFloatToFloat3(w)};
        case 2: return {HashFloat2ToFloat(p.x, p.y), HashFloat2ToFloat3(p.x, p.y)};
        case 3: return {HashFloat3ToFloat(p.x, p.y, p.z), HashFloat3ToFloat3(p.x, p.y, p.z)};
        default: return {HashFloat4ToFloat(p.x, p.y, p.z, w), HashFloat4ToFloat3(p.x, p.y, p.z, w)};
    }
}

float GradientTexture(const GradientTextureParams& params, Vec3f p) {
    const float x = p.x, y = p.y, z = p.z;
    float f = 0.0f;
    switch (params.type) {
        case GradientType::kLinear: f = x; break;
        case GradientType::kQuadratic: {
            const float r = std::fmax(x, 0.0f);
            f = r * r;
            break;
        }
        case GradientType::kEasing: {
            const float r = std::fmin(std::fmax(x, 0.0f), 1.0f);
            const float t = r * r;
            f = 3.0f * t - 2.0f * t * r;
            break;
        }
        case GradientType::kDiagonal: f = (x + y) * 0.5f; break;
        case GradientType::kRadial: f = std::atan2(y, x) / kPi2 + 0.5f; break;
        case GradientType::kQuadraticSphere:
        case GradientType::kSpherical: {
            // The bias gives exactly 0 on a unit vector instead of a float-precision residue.
            const float r = std::fmax(0.999999f - std::sqrt(x * x + y * y + z * z), 0.0f);
            f = params.type == GradientType::kQuadraticSphere ? r * r : r;
            break;
        }
    }
    return Clamp(f, 0.0f, 1.0f);
}

ColorFacOutput CheckerTexture(const CheckerTextureParams& params, Vec3f p) {
    p *= params.scale;
    // The shift keeps unit coordinates (a cube's faces) off the cell boundaries.
    const auto parity = [](float c) {
        const int i = FloorToInt((c + 0.000001f) * 0.999999f);
        return i == INT32_MIN ? 0 : std::abs(i) % 2;  // |INT_MIN| wraps to INT_MIN (even) in Cycles
    };
    const float fac = ((parity(p.x) == parity(p.y)) == (parity(p.z) != 0)) ? 1.0f : 0.0f;
    return {fac == 1.0f ? params.color1 : params.color2, fac};
}

float WaveTexture(const WaveTextureParams& params, Vec3f p) {
    p *= params.scale;
    p = (p + Vec3f(0.000001f, 0.000001f, 0.000001f)) * 0.999999f;  // off unit coordinates, as Checker
    float n;
    if (params.type == WaveType::kBands) {
        switch (params.bands_direction) {
            case WaveBandsDirection::kX: n = p.x * 20.0f; break;
            case WaveBandsDirection::kY: n = p.y * 20.0f; break;
            case WaveBandsDirection::kZ: n = p.z * 20.0f; break;
            default: n = (p.x + p.y + p.z) * 10.0f; break;
        }
    } else {
        Vec3f rp = p;
        switch (params.rings_direction) {
            case WaveRingsDirection::kX: rp.x = 0.0f; break;
            case WaveRingsDirection::kY: rp.y = 0.0f; break;
            case WaveRingsDirection::kZ: rp.z = 0.0f; break;
            default: break;
        }
        n = std::sqrt(rp.x * rp.x + rp.y * rp.y + rp.z * rp.z) * 20.0f;
    }
    n += params.phase_offset;
    if (params.distortion != 0.0f) {
        const Vec3f q = p * params.detail_scale;
        n += params.distortion *
             (FractalNoise(TexVec<3>{{q.x, q.y, q.z}}, params.detail, params.detail_roughness) * 2.0f - 1.0f);
    }
    switch (params.profile) {
        case WaveProfile::kSin: return 0.5f + 0.5f * std::sin(n - kPiOver2);
        case WaveProfile::kSaw: n /= kPi2; return n - Floor(n);
        default: n /= kPi2; return std::fabs(n - Floor(n + 0.5f)) * 2.0f;
    }
}

ColorFacOutput MagicTexture(const MagicTextureParams& params, Vec3f p) {
    // fmod keeps sin/cos arguments small: huge coordinates neither overflow to NaN nor band.
    const float px = std::fmod(p.x, kPi2), py = std::fmod(p.y, kPi2), pz = std::fmod(p.z, kPi2);
    const float scale = params.scale;
    float distortion = params.distortion;
    const int n = params.depth;
    float x = std::sin((px + py + pz) * 5.0f * scale);
    float y = std::cos((-px + py - pz) * 5.0f * scale);
    float z = -std::cos((-px - py + pz) * 5.0f * scale);
    // Each level of depth folds one coordinate through a sine or cosine of the others.
    if (n > 0) {
        x *= distortion;
        y *= distortion;
        z *= distortion;
        y = -std::cos(x - y + z);
        y *= distortion;
        if (n > 1) {
            x = std::cos(x - y - z);
            x *= distortion;
            if (n > 2) {
                z = std::sin(-x - y - z);
                z *= distortion;
                if (n > 3) {
                    x = -std::cos(-x + y - z);
                    x *= distortion;
                    if (n > 4) {
                        y = -std::sin(-x + y + z);
                        y *= distortion;
                        if (n > 5) {
                            y = -std::cos(-x + y + z);
                            y *= distortion;
                            if (n > 6) {
                                x = std::cos(x + y + z);
                                x *= distortion;
                                if (n > 7) {
                                    z = std::sin(x + y - z);
                                    z *= distortion;
                                    if (n > 8) {
                                        x = -std::cos(-x - y + z);
                                        x *= distortion;
                                        if (n > 9) {
                                            y = -std::sin(x - y + z);
                                            y *= distortion;
                                        }
                                    }
                                }
                            }
                        }
                    }
                }
            }
        }
    }
    if (distortion != 0.0f) {
        distortion *= 2.0f;
        x /= distortion;
        y /= distortion;
        z /= distortion;
    }
    const Vec3f color{0.5f - x, 0.5f - y, 0.5f - z};
    return {color, (color.x + color.y + color.z) * (1.0f / 3.0f)};
}

namespace {
// Cycles' brick_noise: a fast integer hash to [0, 1) per brick.
float BrickNoise(uint32_t n) {
    n = (n + 1013) & 0x7fffffff;
    n = (n >> 13) ^ n;
    const uint32_t nn = (n * (n * n * 60493 + 19990303) + 1376312589) & 0x7fffffff;
    return 0.5f * (float(nn) / 1073741824.0f);
}
}  // namespace

ColorFacOutput BrickTexture(const BrickTextureParams& params, Vec3f p) {
    p *= params.scale;
    float brick_width = params.brick_width;
    const float row_height = params.row_height;
    float offset = 0.0f;
    const int row = FloorToInt(p.y / row_height);
    // Every squash_frequency-th row is squashed, every offset_frequency-th shifted (both or neither apply).
    if (params.offset_frequency && params.squash_frequency) {
        brick_width *= (row % params.squash_frequency) ? 1.0f : params.squash;
        offset = (row % params.offset_frequency) ? 0.0f : (brick_width * params.offset);
    }
    const int brick = FloorToInt((p.x + offset) / brick_width);
    const float x = (p.x + offset) - brick_width * float(brick);
    const float y = p.y - row_height * float(row);
    const float tint = Clamp(BrickNoise((uint32_t(row) << 16) + uint32_t(brick & 0xFFFF)) + params.bias, 0.0f, 1.0f);
    float min_dist = std::min(std::min(x, y), std::min(brick_width - x, row_height - y));
    float mortar;
    if (min_dist >= params.mortar_size) {
        mortar = 0.0f;
    } else if (params.mortar_smooth == 0.0f) {
        mortar = 1.0f;
    } else {
        min_dist = 1.0f - min_dist / params.mortar_size;
        if (min_dist < params.mortar_smooth) {
            const float t = min_dist / params.mortar_smooth, tt = t * t;
            mortar = 3.0f * tt - 2.0f * tt * t;
        } else {
            mortar = 1.0f;
        }
    }
    Vec3f color1 = params.color1;
    if (mortar != 1.0f) color1 = params.color1 * (1.0f - tint) + params.color2 * tint;
    return {color1 * (1.0f - mortar) + params.mortar * mortar, mortar};
}

}  // namespace sphrect::render::svm
