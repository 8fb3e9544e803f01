// What a camera ray in a medium meets before the hit it shades, found once in the camera stage and read by every
// technique's shading: its stretches through object volumes (a scene with them), and the transparent surfaces it went
// through (a scene with a medium and transparency), each of which weights the scattering past it by its transparency.
#pragma once

#include <array>

#include "render/object_volumes.h"
#include "render/scene.h"

namespace sphrect::render {

// A transparent surface the camera ray went through at t, and its throughput past it (transparency.h).
struct TransparentPassage {
    float t;
    Spectrum throughput;
};

struct CameraRayMedia {
    VolumeSegments volumes;  // with object volumes (ObjectVolumes::Segments)
    int passage_count = 0;
    std::array<TransparentPassage, kMaxTransparentHits> passages;

    // The camera ray's throughput at t: past the transparent surfaces before it (1 before the first).
    Spectrum ThroughputAt(float t) const {
        Spectrum throughput{1, 1, 1};
        for (int i = 0; i < passage_count && passages[size_t(i)].t <= t; ++i)
            throughput = passages[size_t(i)].throughput;
        return throughput;
    }
};

// Whether the medium kernel keeps a CameraRayMedia per camera sample of `scene`.
inline bool KeepsCameraRayMedia(const RenderScene& scene) {
    return scene.has_volumes || (scene.has_medium && scene.has_transparency);
}

}  // namespace sphrect::render
