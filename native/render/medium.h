// Homogeneous participating medium filling the scene: its coefficients and transmittance, and the names
// of the ways of choosing a scattering distance.  Its phase function is phase_function.h, the distance
// samplings distance_sampling.h (Kulla & Fajardo, EGSR 2012), both included here.
#pragma once

#include <array>
#include <cmath>

#include "distance_sampling.h"
#include "phase_function.h"
#include "sampling_util.h"

namespace sphrect::render {

struct HomogeneousMedium {
    Spectrum sigma_s, sigma_t;  // scattering and extinction (= scattering + absorption), 1/m
    float g = 0;                // Henyey-Greenstein anisotropy, in (-1, 1)
    float sigma_sampling = 0;   // extinction used by distance sampling: mean of sigma_t's channels
};

// sigma_t d per channel; a channel with sigma_t = 0 stays 0 even at d = infinity.
inline Spectrum OpticalDepth(const Spectrum& sigma_t, float d) {
    auto depth = [d](float s) { return s > 0 ? s * d : 0.0f; };
    return {depth(sigma_t.x), depth(sigma_t.y), depth(sigma_t.z)};
}

// exp(-tau) per channel: the transmittance of optical depth tau.
inline Spectrum TransmittanceOfDepth(const Spectrum& tau) {
    return {std::exp(-tau.x), std::exp(-tau.y), std::exp(-tau.z)};
}

// exp(-sigma_t d) per channel; a channel with sigma_t = 0 is 1 even at d = infinity.
inline Spectrum Transmittance(const HomogeneousMedium& m, float d) {
    return TransmittanceOfDepth(OpticalDepth(m.sigma_t, d));
}

// Transmittance along a segment of length d in a kernel compiled with a medium (kMedium), or 1.
template <bool kMedium>
inline Spectrum SegmentTransmittance(const HomogeneousMedium& m, float d) {
    if constexpr (kMedium) return Transmittance(m, d);
    return {1, 1, 1};
}

// How the scattering distance along a camera ray is chosen: both strategies of distance_sampling.h
// combined by MIS, or one of them alone.
enum class MediumSampling { Mis, Distance, EquiAngular };

constexpr std::array<MediumSampling, 3> kAllMediumSamplings = {MediumSampling::Mis, MediumSampling::Distance,
                                                               MediumSampling::EquiAngular};

constexpr const char* MediumSamplingName(MediumSampling m) {
    switch (m) {
        case MediumSampling::Mis: return "mis";
        case MediumSampling::Distance: return "distance";
        case MediumSampling::EquiAngular: return "equiangular";
    }
    return "?";
}

}  // namespace sphrect::render
