// The integrator: direct lighting at the first hit, emission seen directly, and single
// scattering in a homogeneous medium, all estimated per camera sample.
//
// Light selection: one area light per light sample, chosen by power (LightSelector); delta
// lights are all evaluated once per camera sample (and at every scattering point).
// MIS (Veach 1997): each light sample is paired with one BSDF (or, in the medium, phase-function)
// sample whose direction finds the area lights it crosses (intersected analytically: lights are
// not in Embree's scene); the background is reached only by BSDF/phase rays (weight 1).  Lights
// do not occlude anything (they are transparent, as in Cycles).
// Visibility: shading queues every contribution with the occlusion ray it depends on -- to the
// light sample, the delta light, the light or the background a BSDF/phase ray reaches -- and a
// chunk's rays are traced together after its shading (ResolveShadowRays).  A BSDF/phase ray that
// reaches no emitter is not traced at all.
#include "kernel.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <type_traits>
#include <utility>

#if defined(__x86_64__) || defined(__i386__)
#include <x86intrin.h>
#endif

#include "core/rng.h"
#include "embree_rays.h"

namespace sphrect::render {

uint64_t ReadTicks() {
#if defined(__x86_64__) || defined(__i386__)
    return __rdtsc();
#else
    return uint64_t(std::chrono::duration_cast<std::chrono::nanoseconds>(
                        std::chrono::steady_clock::now().time_since_epoch()).count());
#endif
}

struct SurfaceHit {
    Vec3f p;       // hit point
    Vec3f ng;      // unit geometric normal, on the side the camera ray came from
    Vec3f ns;      // unit shading normal, flipped with ng
    float t = 0;   // distance along the camera ray
    int material = 0;
};

struct PrimaryHit {
    Ray ray;
    float t_end = kInf;   // end of the camera ray's segment: surface hit or escape
    bool hit = false;
    SurfaceHit surface;
    Spectrum seen;        // technique-independent part: visible lights before the surface, background
    uint64_t rng_seed = 0;
};

// A shadow ray whose contribution counts for camera sample `sample` if nothing blocks it.
// Shading queues them; a chunk's are traced after its shading as one Embree stream
// (ResolveShadowRays), in place: the stride skips the payload.
struct DeferredShadowRay {
    RTCRay ray;
    Spectrum contribution;
    uint32_t sample;
};

ThreadScratch::ThreadScratch() = default;
ThreadScratch::~ThreadScratch() = default;

namespace {

using Clock = std::chrono::steady_clock;

// Salts of the sample dimensions (DimensionSeed); each gets its own pattern seed per pixel.
enum Dimension : uint64_t { kDimPixel = 1, kDimLens = 2, kDimLight = 3, kDimBsdf = 4, kDimRng = 5 };

// Where shading sends its shadow rays: the queue, the camera sample they belong to, and the
// factor the caller multiplies this estimate by (transmittance, MIS and pdf weights, 1 / samples).
struct ShadowSink {
    std::vector<DeferredShadowRay>* queue;
    uint32_t sample;
    Spectrum scale{1, 1, 1};

    ShadowSink Scaled(const Spectrum& f) const { return {queue, sample, scale * f}; }
    ShadowSink Scaled(float f) const { return {queue, sample, scale * f}; }
    void Add(const Vec3f& o, const Vec3f& d, float dist, const Spectrum& contribution) const {
        queue->push_back({MakeRTCRay(o, d, 0, ShadowRayLength(dist)), contribution * scale, sample});
    }
};

// Traces the queued shadow rays and adds the unblocked contributions to their camera samples.
// One incoherent stream call (rtcOccluded1M): renders 6-29% faster than with a call per ray, most
// with several light samples.  (Flagged coherent, the same stream was 2x slower: the rays
// start all over the chunk's tile.)
void ResolveShadowRays(RTCScene scene, std::vector<DeferredShadowRay>& queue, Spectrum* sample_values) {
    if (queue.empty()) return;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);  // RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT
    rtcOccluded1M(scene, &ctx, &queue[0].ray, unsigned(queue.size()), sizeof(DeferredShadowRay));
    for (const DeferredShadowRay& q : queue)
        if (q.ray.tfar >= 0) sample_values[q.sample] += q.contribution;
}

SurfaceHit MakeSurfaceHit(const RenderScene& scene, const Ray& ray, const RTCRayHit& rh) {
    const MeshData& m = scene.meshes[rh.hit.geomID];
    const uint32_t tri = rh.hit.primID;
    SurfaceHit s;
    s.t = rh.ray.tfar;
    Vec3f ng(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);  // Embree's unnormalised geometric normal
    const float len = Length(ng);
    ng = len > 0 ? ng / len : -ray.d;
    Vec3f ns = ng;
    if (m.normals.empty()) {
        s.p = ray.o + ray.d * s.t;  // flat shading: no vertex fetch needed
    } else {
        // Interpolated shading normal (and the point from the barycentrics, which is more precise).
        const uint32_t i0 = m.triangles[3 * tri], i1 = m.triangles[3 * tri + 1], i2 = m.triangles[3 * tri + 2];
        auto vertex = [&](uint32_t i) { return Vec3f(m.vertices[3 * i], m.vertices[3 * i + 1], m.vertices[3 * i + 2]); };
        const float b1 = rh.hit.u, b2 = rh.hit.v, b0 = 1 - b1 - b2;
        s.p = vertex(i0) * b0 + vertex(i1) * b1 + vertex(i2) * b2;
        const Vec3f n = m.normals[i0] * b0 + m.normals[i1] * b1 + m.normals[i2] * b2;
        const float ln = Length(n);
        if (ln > 0) ns = n / ln;
        if (Dot(ns, ng) < 0) ns = -ns;  // shading normal on the geometric normal's side
    }
    // Surfaces are two-sided: both normals face the incoming ray.
    if (Dot(ng, ray.d) > 0) {
        ng = -ng;
        ns = -ns;
    }
    s.ng = ng;
    s.ns = ns;
    s.material = m.material_ids.empty() ? 0 : m.material_ids[tri];
    return s;
}

// Everything the shading code needs, fixed for a pass.
struct ShadeContext {
    const RenderScene& scene;
    MisMode mis;
    MediumSampling medium_sampling;
    int light_samples;
    bool sample_bsdf;  // BSDF/phase samples are drawn: MIS on, or a background to find
    Spectrum sky;      // what a BSDF/phase ray that escapes brings: background x transmittance to infinity
};

template <bool kMedium>
inline Spectrum SegmentTransmittance(const RenderScene& scene, float d) {
    if constexpr (kMedium) return Transmittance(scene.medium, d);
    return {1, 1, 1};
}

// The medium has no normal: the cosine-weighted technique would drop light behind its
// made-up horizon, so scattering points use the spherical rectangle instead.
template <Technique K>
constexpr Technique kMediumTechnique = K == Technique::RectangleCosine ? Technique::Rectangle : K;

// Light sampling at one shading or scattering point (origin, normal): a point on area light
// `index` by technique K on rectangles, uniformly by area on ellipses.  A rectangle's sampler
// is set up once per (point, light) and kept for the following samples of that light and for
// the MIS pdfs of the paired BSDF/phase rays.  Time spent is added to `ticks`.
template <Technique K>
class LightSamplingAt {
  public:
    LightSamplingAt(const RenderScene& scene, const Vec3f& origin, const Vec3f& normal, uint64_t& ticks)
        : scene_(scene), origin_(origin), normal_(normal), ticks_(ticks) {}

    LightSample<float> Sample(int index, Point2<float> u) {
        const uint64_t t0 = ReadTicks();
        const AreaLight& l = scene_.area_lights[index];
        LightSample<float> ls;
        if (l.shape == AreaShape::Ellipse) {
            ls = SampleEllipseArea(l, origin_, u);
        } else {
            if (index != cached_index_) {
                cached_.emplace(origin_, normal_, l.frame);
                cached_index_ = index;
            }
            if (cached_->Valid()) ls = cached_->Sample(u);
        }
        ticks_ += ReadTicks() - t0;
        return ls;
    }

    // Solid-angle pdf with which Sample, after choosing the light by power, produces point p
    // on area light `index`.
    float PDF(int index, const Vec3f& p) {
        const AreaLight& l = scene_.area_lights[index];
        const float pmf = scene_.light_selector.pmf[index];
        if (!(pmf > 0)) return 0;
        const uint64_t t0 = ReadTicks();
        float pdf;
        if (l.shape == AreaShape::Ellipse) {
            pdf = EllipseAreaPDF(l, origin_, p);
        } else if (index == cached_index_) {
            pdf = cached_->Pdf(p);
        } else {
            const LightSampler<K, float> s(origin_, normal_, l.frame);
            pdf = s.Valid() ? s.Pdf(p) : 0.0f;
        }
        ticks_ += ReadTicks() - t0;
        return pmf * pdf;
    }

  private:
    const RenderScene& scene_;
    Vec3f origin_, normal_;
    uint64_t& ticks_;
    std::optional<LightSampler<K, float>> cached_;  // set up for rectangle light `cached_index_`
    int cached_index_ = -1;
};

// What a BSDF or phase sample's ray (o, d) reaches, each queued with an occlusion ray up to it:
// the background where the ray escapes, and with MIS every area light it crosses, weighted
// against light sampling (Le T w).  A light counts when no surface lies before it -- the same
// test as for its light samples -- so a ray that reaches no emitter is not traced at all.
// pdf_dir: the direction's pdf under BSDF/phase sampling; `sink` carries its weight f cos / pdf.
template <Technique K, bool kMedium>
void QueueEmittersAlongRay(const ShadeContext& c, const Vec3f& o, const Vec3f& d, float pdf_dir,
                           LightSamplingAt<K>& light_sampling, const ShadowSink& sink, TechniqueTally& tally) {
    if (!IsBlack(c.sky)) {
        ++tally.rays;
        sink.Add(o, d, kInf, c.sky);
    }
    if (c.mis == MisMode::None) return;
    const auto& lights = c.scene.area_lights;
    for (int i = 0; i < int(lights.size()); ++i) {
        const float t = IntersectAreaLight(lights[i], o, d, kInf);
        if (std::isinf(t)) continue;
        const Spectrum le = EmittedRadiance(lights[i], -d);
        if (IsBlack(le)) continue;
        const float pdf_light = light_sampling.PDF(i, o + d * t);
        ++tally.rays;
        sink.Add(o, d, t, le * SegmentTransmittance<kMedium>(c.scene, t) * MisWeight(c.mis, pdf_dir, pdf_light));
    }
}

// Direct light reflected at a surface point towards wo_world, all queued on `sink` with its
// occlusion rays: light samples (technique K) and, for MIS and the background, BSDF samples,
// averaged over the light samples; delta lights once.
template <Technique K, bool kGlossy, bool kMedium>
void DirectLightAtSurface(const ShadeContext& c, const SurfaceHit& h, const Vec3f& wo_world,
                          const Point2<float>* light_points, const Point2<float>* bsdf_points, PCG32& rng,
                          const ShadowSink& sink, TechniqueTally& tally) {
    const RenderScene& scene = c.scene;
    const Material& mat = scene.materials[h.material];
    const Frame frame = Frame::FromZ(h.ns);
    const Vec3f wo = frame.ToLocal(wo_world);
    if (wo.z <= 0) return;
    const Vec3f origin = OffsetOrigin(h.p, h.ng);
    const ShadowSink light_sink = sink.Scaled(1.0f / c.light_samples);
    // Without area lights and BSDF samples (only delta lights) there is nothing to sample.
    const int n_pairs = (!scene.light_selector.Empty() || c.sample_bsdf) ? c.light_samples : 0;
    LightSamplingAt<K> light_sampling(scene, h.p, h.ns, tally.light_ticks);
    for (int j = 0; j < n_pairs; ++j) {
        int chosen = -1;
        float pmf = 0;
        if (!scene.light_selector.Empty()) {
            chosen = scene.light_selector.Select(rng.NextFloat());
            pmf = scene.light_selector.pmf[chosen];
        }
        const AreaLight* light = chosen >= 0 ? &scene.area_lights[chosen] : nullptr;
        const LightSample<float> ls = light ? light_sampling.Sample(chosen, light_points[j]) : LightSample<float>{};
        if (ls.pdf > 0 && std::isfinite(ls.pdf)) {
            const Spectrum le = EmittedRadiance(*light, -ls.dir);
            const Vec3f wi = frame.ToLocal(ls.dir);
            if (!IsBlack(le) && wi.z > 0 && Dot(ls.dir, h.ng) > 0) {
                const Spectrum f = EvalBsdf<kGlossy>(mat, wo, wi);
                if (!IsBlack(f)) {
                    const float pdf_light = pmf * ls.pdf;
                    const float w = c.mis == MisMode::None
                                        ? 1.0f
                                        : MisWeight(c.mis, pdf_light, BsdfPDF<kGlossy>(mat, wo, wi));
                    ++tally.rays;
                    light_sink.Add(origin, ls.dir, ls.dist,
                                   f * le * SegmentTransmittance<kMedium>(scene, ls.dist) * (wi.z * w / pdf_light));
                }
            }
        }
        // BSDF sample: finds area lights (MIS partner) and the background.
        if (c.sample_bsdf) {
            const BsdfSample bs = SampleBsdf<kGlossy>(mat, wo, bsdf_points[j]);
            if (bs.pdf > 0) {
                const Vec3f wi_world = frame.FromLocal(bs.wi);
                if (Dot(wi_world, h.ng) > 0)
                    QueueEmittersAlongRay<K, kMedium>(c, origin, wi_world, bs.pdf, light_sampling,
                                                      light_sink.Scaled(bs.f * (bs.wi.z / bs.pdf)), tally);
            }
        }
    }
    for (const DeltaLight& d : scene.delta_lights) {
        const DeltaIllumination di = IlluminateFromDelta(d, h.p);
        if (IsBlack(di.li) || Dot(di.wi, h.ng) <= 0) continue;
        const Vec3f wi = frame.ToLocal(di.wi);
        if (wi.z <= 0) continue;
        const Spectrum f = EvalBsdf<kGlossy>(mat, wo, wi);
        if (IsBlack(f)) continue;
        ++tally.rays;
        sink.Add(origin, di.wi, di.dist, f * di.li * SegmentTransmittance<kMedium>(scene, di.dist) * wi.z);
    }
}

// Light scattered towards the camera at x (single scattering): sigma_s * integral of
// phase * Le * T over the lights, estimated with one light sample (technique K, for the area
// light `chosen`) and one phase sample; delta lights in full.  Phase and pdfs are w.r.t. wi.
template <Technique K>
void InScatteredLight(const ShadeContext& c, const Vec3f& x, const Vec3f& ray_dir, int chosen, Point2<float> light_point,
                      Point2<float> phase_point, const ShadowSink& sink, TechniqueTally& tally) {
    constexpr Technique MK = kMediumTechnique<K>;
    const RenderScene& scene = c.scene;
    const float g = scene.medium.g;
    const ShadowSink out = sink.Scaled(scene.medium.sigma_s);
    const AreaLight* light = chosen >= 0 ? &scene.area_lights[chosen] : nullptr;
    const float pmf = chosen >= 0 ? scene.light_selector.pmf[chosen] : 0.0f;
    LightSamplingAt<MK> light_sampling(scene, x, ray_dir, tally.light_ticks);
    const LightSample<float> ls = light ? light_sampling.Sample(chosen, light_point) : LightSample<float>{};
    if (ls.pdf > 0 && std::isfinite(ls.pdf)) {
        const Spectrum le = EmittedRadiance(*light, -ls.dir);
        if (!IsBlack(le)) {
            const float phase = HenyeyGreenstein(Dot(ls.dir, ray_dir), g);
            const float pdf_light = pmf * ls.pdf;
            const float w = MisWeight(c.mis, pdf_light, phase);
            ++tally.rays;
            out.Add(x, ls.dir, ls.dist, le * Transmittance(scene.medium, ls.dist) * (phase * w / pdf_light));
        }
    }
    if (c.sample_bsdf) {
        // Phase sampling: the weight phase / pdf is 1.
        const Vec3f wi = SampleHenyeyGreenstein(ray_dir, g, phase_point);
        const float pdf_phase = HenyeyGreenstein(Dot(wi, ray_dir), g);
        QueueEmittersAlongRay<MK, true>(c, x, wi, pdf_phase, light_sampling, out, tally);
    }
    for (const DeltaLight& d : scene.delta_lights) {
        const DeltaIllumination di = IlluminateFromDelta(d, x);
        if (IsBlack(di.li)) continue;
        ++tally.rays;
        out.Add(x, di.wi, di.dist, di.li * Transmittance(scene.medium, di.dist) * HenyeyGreenstein(Dot(di.wi, ray_dir), g));
    }
}

// Single scattering along the camera ray's segment [0, t_end): integral of T(t) * inscattered(t),
// with distance sampling and equi-angular sampling (about the chosen light's centre), combined
// by one-sample-per-strategy MIS (the renderer's heuristic; balance when MIS is off).  The
// equi-angular centre is a random light; for each choice the combination is unbiased, so the
// mixture is too.
template <Technique K>
void SingleScattering(const ShadeContext& c, const PrimaryHit& ph, const Point2<float>* light_points,
                      const Point2<float>* bsdf_points, PCG32& rng, const ShadowSink& sink, TechniqueTally& tally) {
    const RenderScene& scene = c.scene;
    const HomogeneousMedium& med = scene.medium;
    const Ray& ray = ph.ray;
    const MisMode strategy_mis = c.mis == MisMode::None ? MisMode::Balance : c.mis;
    const float per_sample = 1.0f / c.light_samples;
    const bool has_centre = !scene.medium_centre_selector.Empty();
    for (int j = 0; j < c.light_samples; ++j) {
        // The area light for the light sample at the scattering point, and (independently) the
        // centre for equi-angular sampling: any area, point or spot light, by power.
        const int chosen = scene.light_selector.Empty() ? -1 : scene.light_selector.Select(rng.NextFloat());
        const float u_centre = rng.NextFloat();
        const Vec3f centre =
            has_centre ? scene.medium_centres[scene.medium_centre_selector.Select(u_centre)] : Vec3f();
        const EquiAngular ea = has_centre ? MakeEquiAngular(ray.o, ray.d, ph.t_end, centre) : EquiAngular{};
        const bool use_equi = c.medium_sampling != MediumSampling::Distance && ea.valid;
        const bool use_distance = c.medium_sampling != MediumSampling::EquiAngular || !ea.valid;
        const float u_distance = rng.NextFloat(), u_equi = rng.NextFloat();
        if (use_distance) {
            const float t = SampleExponentialDistance(med.sigma_sampling, u_distance);
            if (t < ph.t_end) {
                const float pdf = ExponentialDistancePDF(med.sigma_sampling, t);
                const float w = use_equi ? MisWeight(strategy_mis, pdf, EquiAngularPDF(ea, t)) : 1.0f;
                if (pdf > 0 && w > 0) {
                    const Spectrum weight = Transmittance(med, t) * (w / pdf);
                    InScatteredLight<K>(c, ray.o + ray.d * t, ray.d, chosen, light_points[j], bsdf_points[j],
                                        sink.Scaled(weight * per_sample), tally);
                }
            }
        }
        if (use_equi) {
            const float t = SampleEquiAngular(ea, u_equi);
            const float pdf = EquiAngularPDF(ea, t);
            if (t > 0 && t < ph.t_end && pdf > 0 && std::isfinite(pdf)) {
                const float w =
                    use_distance ? MisWeight(strategy_mis, pdf, ExponentialDistancePDF(med.sigma_sampling, t)) : 1.0f;
                if (w > 0) {
                    const Spectrum weight = Transmittance(med, t) * (w / pdf);
                    InScatteredLight<K>(c, ray.o + ray.d * t, ray.d, chosen, light_points[j], bsdf_points[j],
                                        sink.Scaled(weight * per_sample), tally);
                }
            }
        }
    }
}

// Everything a camera sample receives beyond what it sees directly, queued on `sink`.
template <Technique K, bool kGlossy, bool kMedium>
inline void ShadeCameraSample(const ShadeContext& c, const PrimaryHit& ph, const Point2<float>* light_points,
                              const Point2<float>* bsdf_points, const ShadowSink& sink, TechniqueTally& tally) {
    PCG32 rng(ph.rng_seed, 0x5851f42dull);
    if (ph.hit)
        DirectLightAtSurface<K, kGlossy, kMedium>(c, ph.surface, -ph.ray.d, light_points, bsdf_points, rng,
                                                  sink.Scaled(SegmentTransmittance<kMedium>(c.scene, ph.surface.t)),
                                                  tally);
    // (The run-time test only matters for the benchmark's forced all-features kernel.)
    if constexpr (kMedium)
        if (c.scene.has_medium) SingleScattering<K>(c, ph, light_points, bsdf_points, rng, sink, tally);
}

// Traces the camera rays of out[0..n) into hits[0..n) as one coherent stream: a chunk's
// camera rays leave one point (a small lens; or are parallel) and cover one tile, so Embree's
// packet traversal is ~40% faster on them than ray by ray.
void TraceCameraRays(RTCScene scene, const PrimaryHit* out, size_t n, RTCRayHit* hits) {
    for (size_t i = 0; i < n; ++i) hits[i] = MakeRTCRayHit(out[i].ray.o, out[i].ray.d, out[i].ray.tmin, out[i].ray.tmax);
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    rtcIntersect1M(scene, &ctx, hits, unsigned(n), sizeof(RTCRayHit));
}

// The camera ray's first hit, and what it sees directly (shared by all techniques).
template <bool kMedium>
void FinishCameraSample(const RenderScene& scene, const RTCRayHit& rh, PrimaryHit& out) {
    out.hit = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    out.t_end = out.hit ? rh.ray.tfar : kInf;
    if (out.hit) out.surface = MakeSurfaceHit(scene, out.ray, rh);
    Spectrum seen;
    for (const AreaLight& l : scene.area_lights) {
        if (!l.visible) continue;
        const float t = IntersectAreaLight(l, out.ray.o, out.ray.d, std::min(out.t_end, out.ray.tmax));
        if (std::isinf(t) || t < out.ray.tmin) continue;
        seen += EmittedRadiance(l, -out.ray.d) * SegmentTransmittance<kMedium>(scene, t);
    }
    if (!out.hit) seen += scene.background * SegmentTransmittance<kMedium>(scene, kInf);
    out.seen = seen;
}

// Pixels are processed in chunks of at most ~kChunkSamples camera samples and ~kChunkLightSamples
// light samples (each queues its occlusion rays): first the camera stage for the whole chunk, then
// each technique over it, so timers run once per chunk and the buffers stay small whatever the
// sample counts.
constexpr uint64_t kChunkSamples = 1024, kChunkLightSamples = 4096;

template <bool kDof, bool kGlossy, bool kMedium>
void RenderTile(const KernelParams& p, const TileRect& tile, ThreadScratch& scratch, TileTally& tally) {
    const RenderScene& scene = *p.scene;
    const RenderOptions& opt = *p.options;
    const int w = scene.camera.width;
    const uint32_t n = uint32_t(p.samples), nl = uint32_t(opt.light_samples);
    const int tile_w = tile.x1 - tile.x0, tile_pixels = tile_w * (tile.y1 - tile.y0);
    const int chunk_pixels = int(std::clamp<uint64_t>(std::min(kChunkSamples / n, kChunkLightSamples / (uint64_t(n) * nl)),
                                                      1, uint64_t(tile_pixels)));
    const size_t chunk_samples = size_t(chunk_pixels) * n;
    scratch.hits.resize(chunk_samples);
    scratch.camera_hits.resize(chunk_samples);
    scratch.sample_values.resize(chunk_samples);
    Spectrum* const values = scratch.sample_values.data();
    scratch.pixel_points.resize(n);
    scratch.lens_points.resize(n);
    scratch.light_points.resize(chunk_samples * nl);
    scratch.bsdf_points.resize(chunk_samples * nl);
    const ShadeContext ctx{scene, opt.mis, opt.medium_sampling, opt.light_samples,
                           opt.mis != MisMode::None || !IsBlack(scene.background),
                           scene.background * SegmentTransmittance<kMedium>(scene, kInf)};
    tally.technique.resize(opt.techniques.size());
    std::vector<Spectrum> pixel_sums(size_t(chunk_pixels) * opt.techniques.size());
    for (int first = 0; first < tile_pixels; first += chunk_pixels) {
        const int count = std::min(chunk_pixels, tile_pixels - first);
        auto pixel_x = [&](int c) { return tile.x0 + (first + c) % tile_w; };
        auto pixel_y = [&](int c) { return tile.y0 + (first + c) / tile_w; };
        // Camera stage.
        const auto c0 = Clock::now();
        for (int c = 0; c < count; ++c) {
            const int x = pixel_x(c), y = pixel_y(c);
            const uint64_t pixel = uint64_t(y) * w + x;
            const uint64_t pixel_seed = MixBits(MixBits(opt.seed + 0x632be59bd9b4e019ull) ^ (pixel + 1));
            SampleDimensionPoints(opt.pattern, n, p.first_sample, p.pass, DimensionSeed(pixel_seed, kDimPixel), false,
                        scratch.pixel_points.data());
            if constexpr (kDof)
                SampleDimensionPoints(opt.pattern, n, p.first_sample, p.pass, DimensionSeed(pixel_seed, kDimLens), true,
                            scratch.lens_points.data());
            Point2<float>* light_points = &scratch.light_points[size_t(c) * n * nl];
            SampleDimensionPoints(opt.pattern, n * nl, p.first_sample * nl, p.pass, DimensionSeed(pixel_seed, kDimLight), true,
                        light_points);
            if (ctx.sample_bsdf)  // BSDF/phase sample positions only when those samples are drawn
                SampleDimensionPoints(opt.pattern, n * nl, p.first_sample * nl, p.pass, DimensionSeed(pixel_seed, kDimBsdf), true,
                            &scratch.bsdf_points[size_t(c) * n * nl]);
            const uint64_t rng_base = DimensionSeed(pixel_seed, kDimRng);
            for (uint32_t i = 0; i < n; ++i) {
                PrimaryHit& ph = scratch.hits[size_t(c) * n + i];
                const Point2<float> jitter = scratch.pixel_points[i];
                ph.ray = GenerateCameraRay<kDof>(scene.camera, x + jitter.u, y + jitter.v,
                                                 kDof ? scratch.lens_points[i] : Point2<float>{});
                ph.rng_seed = MixBits(rng_base ^ (uint64_t(p.first_sample + i) * 0xbf58476d1ce4e5b9ull));
            }
        }
        const size_t chunk_n = size_t(count) * n;
        TraceCameraRays(scene.rtc_scene, scratch.hits.data(), chunk_n, scratch.camera_hits.data());
        for (size_t s = 0; s < chunk_n; ++s) FinishCameraSample<kMedium>(scene, scratch.camera_hits[s], scratch.hits[s]);
        tally.camera_seconds += std::chrono::duration<double>(Clock::now() - c0).count();
        tally.camera_rays += chunk_n;
        // Shading stage, once per technique, over the same camera samples.
        for (size_t k = 0; k < opt.techniques.size(); ++k) {
            TechniqueTally& tt = tally.technique[k];
            const auto s0 = Clock::now();
            DispatchTechnique(opt.techniques[k], [&](auto tag) {
                constexpr Technique K = decltype(tag)::value;
                auto& queue = scratch.shadow_rays;
                queue.clear();
                for (uint32_t s = 0; s < uint32_t(chunk_n); ++s) {
                    values[s] = scratch.hits[s].seen;
                    ShadeCameraSample<K, kGlossy, kMedium>(ctx, scratch.hits[s], &scratch.light_points[s * nl],
                                                           &scratch.bsdf_points[s * nl], ShadowSink{&queue, s}, tt);
                }
            });
            ResolveShadowRays(scene.rtc_scene, scratch.shadow_rays, values);
            for (int c = 0; c < count; ++c) {
                Spectrum sum;
                for (uint32_t i = 0; i < n; ++i) {
                    const Spectrum& l = values[size_t(c) * n + i];
                    // A NaN or inf sample would poison the pixel forever: drop it and count it
                    // (reported in the stats; never expected).
                    if (IsFinite(l)) {
                        sum += l;
                    } else {
                        ++tt.dropped;
                    }
                }
                pixel_sums[k * chunk_pixels + c] = sum;
            }
            tt.total_seconds += std::chrono::duration<double>(Clock::now() - s0).count();
        }
        for (int c = 0; c < count; ++c) {
            const uint64_t pixel = uint64_t(pixel_y(c)) * w + pixel_x(c);
            for (size_t k = 0; k < opt.techniques.size(); ++k) {
                const Spectrum& sum = pixel_sums[k * chunk_pixels + c];
                double* px = p.sums[k] + 3 * pixel;
                px[0] += sum.x;
                px[1] += sum.y;
                px[2] += sum.z;
            }
            p.counts[pixel] += n;
        }
    }
}

template <bool kDof, bool kGlossy>
TileKernel SelectMedium(bool medium) {
    return medium ? &RenderTile<kDof, kGlossy, true> : &RenderTile<kDof, kGlossy, false>;
}
template <bool kDof>
TileKernel SelectGlossy(bool glossy, bool medium) {
    return glossy ? SelectMedium<kDof, true>(medium) : SelectMedium<kDof, false>(medium);
}

}  // namespace

TileKernel SelectTileKernel(bool dof, bool glossy, bool medium) {
    return dof ? SelectGlossy<true>(glossy, medium) : SelectGlossy<false>(glossy, medium);
}

}  // namespace sphrect::render
