// A camera ray's stretches through media (object volumes plus the world medium: integrator/shade_volume.h,
// MakeMediumStretches), and distance sampling through them -- the exponential of distance_sampling.h over a
// piecewise-constant extinction: SampleDistanceThroughStretches inverts the optical depth stretch by stretch,
// DistanceThroughStretchesPDF is its density (the mass past the last stretch: no sample).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

#include "medium.h"
#include "object_volumes.h"
#include "sampling_util.h"

namespace sphrect::render {

// A scattering distance on the camera ray's segment [0, t_end) and its pdf (0: none).
struct ScatterDistance {
    float t = 0, pdf = 0;
};

// A stretch [t0, t1) of the camera ray in media (the volumes' coefficients plus the world medium's), with the optical
// depths before it: tau0 per channel (transmittance) and tau_sampling0 of the distance sampling's extinction.
struct MediumStretch {
    float t0, t1;
    VolumeCoefficients k;
    float sigma_sampling;  // mean of k.sigma_t's channels
    Spectrum tau0;
    float tau_sampling0;
};

// The stretches of [0, t_end) where the medium is not empty, in order.
struct MediumStretches {
    int count = 0;
    std::array<MediumStretch, kMaxVolumeSegments> stretch;

    // The stretch holding t, or null.
    const MediumStretch* At(float t) const {
        for (int i = 0; i < count; ++i)
            if (t >= stretch[i].t0 && t < stretch[i].t1) return &stretch[i];
        return nullptr;
    }
};

// A stretch's coefficients with those of the world medium (if any) added: their anisotropy, the mean weighted by
// sigma_s (an approximation where they differ).
inline VolumeCoefficients WithWorldMedium(const VolumeCoefficients& v, const HomogeneousMedium* world) {
    if (!world) return v;
    const float wv = Average(v.sigma_s), wm = Average(world->sigma_s);
    return {v.sigma_s + world->sigma_s, v.sigma_t + world->sigma_t,
            wv + wm > 0 ? (wv * v.g + wm * world->g) / (wv + wm) : 0};
}

// The stretches of a camera ray's segments (ObjectVolumes::Segments) before t_end where the medium (theirs plus the
// world's, if any) is not empty.
inline MediumStretches MakeMediumStretches(const VolumeSegments& segments, float t_end,
                                           const HomogeneousMedium* world) {
    MediumStretches out;
    Spectrum tau;
    float tau_sampling = 0;
    for (int i = 0; i < segments.count && segments.segment[i].t0 < t_end; ++i) {
        const VolumeSegment& seg = segments.segment[i];
        const VolumeCoefficients k = WithWorldMedium(seg.coefficients, world);
        if (IsBlack(k.sigma_t)) continue;
        const float t1 = std::min(seg.t1, t_end), sigma_sampling = Average(k.sigma_t);
        out.stretch[out.count++] = {seg.t0, t1, k, sigma_sampling, tau, tau_sampling};
        tau += k.sigma_t * (t1 - seg.t0);  // inf past an open end: only ever read through exp(-tau)
        tau_sampling += sigma_sampling * (t1 - seg.t0);
    }
    return out;
}

// Transmittance from the camera to t inside stretch s.
inline Spectrum TransmittanceInStretch(const MediumStretch& s, float t) {
    return TransmittanceOfDepth(s.tau0 + s.k.sigma_t * (t - s.t0));
}

// Distance sampling through the stretches: t with density sigma_sampling(t) exp(-its optical depth to t).
inline ScatterDistance SampleDistanceThroughStretches(const MediumStretches& st, float u) {
    const float tau = -std::log1p(-u);
    for (int i = 0; i < st.count; ++i) {
        const MediumStretch& s = st.stretch[i];
        const float t = s.t0 + (tau - s.tau_sampling0) / s.sigma_sampling;
        if (t < s.t1) return {t, s.sigma_sampling * std::exp(-tau)};
    }
    return {};
}

inline float DistanceThroughStretchesPDF(const MediumStretches& st, float t) {
    const MediumStretch* s = st.At(t);
    if (!s) return 0;
    return s->sigma_sampling * std::exp(-(s->tau_sampling0 + s->sigma_sampling * (t - s->t0)));
}

}  // namespace sphrect::render
