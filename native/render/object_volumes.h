// Object volumes: homogeneous media bounded by closed meshes (Blender's fog boxes -- a mesh whose material has a
// Volume output), as Cycles 3.4 keeps them on its volume stack: a ray enters a volume where it crosses a front face
// of its mesh and leaves it at a back face, and the coefficients of the volumes a point is inside add up (with a
// world medium's, medium.h).
//
// Which volumes a ray's origin lies in is read off the ray itself: a closed mesh's first crossing along the ray is
// a back face exactly when the origin is inside it.  So every query walks the ray to infinity through the volumes'
// boundaries, in their own Embree scene (one traversal whose filter records every crossing), and needs no state
// carried along a path -- the same answer for a camera, a surface point or a scattering point.
#pragma once

#include <embree3/rtcore.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "sampling_util.h"

namespace sphrect::render {

// The most volumes a scene may hold (a bit each in a ray's set of volumes), and the most boundary crossings one
// query records (past them the ray is taken as leaving no volume).
constexpr int kMaxObjectVolumes = 64;
constexpr int kMaxVolumeCrossings = 256;

// A ray's crossing of a volume's boundary at distance t: into it (a front face) or out of it.
struct VolumeCrossing {
    float t;
    uint32_t volume;
    bool entering;
};

struct VolumeCoefficients {
    Spectrum sigma_s, sigma_t;  // 1/m
    float g = 0;                // Henyey-Greenstein anisotropy
};

// A stretch [t0, t1) of a ray in one set of volumes, with their summed coefficients (g: the sigma_s-weighted mean of
// theirs).  An empty set has zero coefficients.
struct VolumeSegment {
    float t0, t1;
    VolumeCoefficients coefficients;
};

// The stretches of a ray from its origin to infinity (the last ends at kInf), in order; past kMaxVolumeSegments
// crossings the last stretch runs on to infinity (truncated).
constexpr int kMaxVolumeSegments = 32;
struct VolumeSegments {
    int count = 0;
    bool truncated = false;
    std::array<VolumeSegment, kMaxVolumeSegments> segment;

    // exp(-integral of sigma_t over [0, t)) per channel.
    Spectrum TransmittanceTo(float t) const;
};

class ObjectVolumes {
  public:
    ObjectVolumes() = default;
    ~ObjectVolumes();
    ObjectVolumes(const ObjectVolumes&) = delete;
    ObjectVolumes& operator=(const ObjectVolumes&) = delete;

    // A volume bounded by the closed mesh (vertices: 3 floats each; triangles: 3 indices each, counter-clockwise seen
    // from outside).  std::invalid_argument naming it on bad input or past kMaxObjectVolumes.
    void Add(RTCDevice device, const std::string& name, const float* vertices, size_t num_vertices,
             const int32_t* triangles, size_t num_triangles, const Spectrum& sigma_s, const Spectrum& sigma_a, float g);
    void Commit(RTCDevice device);
    bool Empty() const { return coefficients_.empty(); }
    size_t Count() const { return coefficients_.size(); }
    const VolumeCoefficients& Coefficients(size_t volume) const { return coefficients_[volume]; }

    // exp(-integral of sigma_t) along o + t d for t in [0, tmax) (tmax may be kInf), d unit.
    Spectrum Transmittance(const Vec3f& o, const Vec3f& d, float tmax) const;
    // The ray's stretches from its origin to infinity; with t_begin > 0 (a camera ray's clip start, where Cycles 3.4
    // moves its origin), the media start there: [0, t_begin) is an empty stretch, and the volumes holding the ray at
    // t_begin are those of the point o + t_begin d.
    void Segments(const Vec3f& o, const Vec3f& d, VolumeSegments& out, float t_begin = 0) const;

  private:
    // The ray's crossings of every boundary (out: kMaxVolumeCrossings of room), sorted by t, and the set of volumes its
    // origin is inside.
    int Crossings(const Vec3f& o, const Vec3f& d, VolumeCrossing* out, uint64_t& inside) const;
    VolumeCoefficients Sum(uint64_t set) const;
    // Whether the ray o + t d, t >= 0, misses the volumes' bounding box (then it crosses none: no walk needed).
    bool MissesBounds(const Vec3f& o, const Vec3f& d) const;
    Vec3f bounds_lo_, bounds_hi_;
    std::vector<VolumeCoefficients> coefficients_;
    std::vector<std::string> names_;
    RTCScene rtc_scene_ = nullptr;
};

}  // namespace sphrect::render
