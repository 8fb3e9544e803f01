// The scene's camera (Cycles: scene/camera.cpp): checked before a scene or a renderer takes it.
#include <cmath>
#include <string>

#include "scene.h"
#include "scene_checks.h"

namespace sphrect::render {

void ValidateCamera(const CameraModel& c) {
    if (c.width <= 0 || c.height <= 0 || c.width > kMaxImageSide || c.height > kMaxImageSide ||
        int64_t(c.width) * c.height > kMaxImagePixels)
        Fail("camera resolution " + std::to_string(c.width) + " x " + std::to_string(c.height) +
             " is out of range (each side 1.." + std::to_string(kMaxImageSide) + ", at most 2^" +
             std::to_string(kMaxImagePixelsLog2) + " pixels)");
    for (const auto& row : c.to_world)
        for (float x : row)
            if (!std::isfinite(x)) Fail("camera matrix must be finite");
    const Vec3f cx = c.VectorToWorld({1, 0, 0}), cy = c.VectorToWorld({0, 1, 0}), cz = c.VectorToWorld({0, 0, 1});
    if (!(std::abs(Dot(Cross(cx, cy), cz)) > 1e-12f)) Fail("camera matrix is singular");
    if (!(c.half_width > 0 && c.half_height > 0 && std::isfinite(c.half_width) && std::isfinite(c.half_height)))
        Fail("camera image plane must have a positive, finite size (check lens, sensor and ortho_scale)");
    if (!std::isfinite(c.offset_x) || !std::isfinite(c.offset_y)) Fail("camera shift must be finite");
    if (!(c.aperture_radius >= 0) || !std::isfinite(c.aperture_radius)) Fail("aperture_radius must be >= 0");
    if (c.aperture_radius > 0 && !(c.focus_distance > 0 && std::isfinite(c.focus_distance)))
        Fail("focus_distance must be positive when aperture_radius > 0");
    if (!(c.clip_start >= 0) || !(c.clip_end > c.clip_start)) Fail("camera clipping needs 0 <= clip_start < clip_end");
}

void RenderScene::SetCamera(const CameraModel& c) {
    RequireNotCommitted();
    ValidateCamera(c);
    camera = c;
    camera_set_ = true;
}

}  // namespace sphrect::render
