// What a renderer renders from: a camera, and what depends on it — the images of the lights it sees on its
// film (the control variate's screen lights) and whether it needs the depth-of-field kernel.  The scene is
// committed with a camera; a Renderer may render from another (Renderer::SetCamera) with the same scene, so
// that a view change in Blender's viewport costs these alone, not the BVH and the light tree.
#pragma once

#include <vector>

#include "camera.h"
#include "scene.h"
#include "screen_lights.h"

namespace sphrect::render {

struct CameraView {
    CameraModel camera;
    std::vector<ScreenLight> screen_lights;  // the analytic lights the camera sees whole (screen_lights.h)
    bool dof = false;                        // a thin lens: the kernel with depth of field
};

// The view of `scene` through `camera` (ValidateCamera'd).
inline CameraView MakeCameraView(const RenderScene& scene, const CameraModel& camera) {
    return {camera, BuildScreenLights(camera, scene.area_lights, scene.num_analytic_lights),
            camera.aperture_radius > 0 && !camera.orthographic};
}

}  // namespace sphrect::render
