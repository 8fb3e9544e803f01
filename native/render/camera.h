// Blender's cameras: perspective (pinhole or thin lens) and orthographic, looking down local -Z
// with +Y up.  The image plane extents and shift come from sphrect.Camera.image_plane() (Python),
// which applies Blender's sensor-fit rules; here (x, y) in pixels, y = 0 at the top of the image.
#pragma once

#include <cmath>

#include "pixel_filter.h"
#include "sampling_util.h"

namespace sphrect::render {

struct CameraModel {
    int width = 64, height = 64;
    bool orthographic = false;
    float to_world[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};  // affine part of the 4x4 matrix
    float half_width = 0.5f, half_height = 0.5f;  // image plane at distance 1 (ortho: world units)
    float offset_x = 0, offset_y = 0;             // shift, same units
    float aperture_radius = 0, focus_distance = 10;
    float clip_start = 0, clip_end = 1e30f;
    PixelFilter filter;  // where in and around its pixel a camera sample looks (pixel_filter.h); default the 1-px box

    Vec3f PointToWorld(const Vec3f& p) const {
        return {to_world[0][0] * p.x + to_world[0][1] * p.y + to_world[0][2] * p.z + to_world[0][3],
                to_world[1][0] * p.x + to_world[1][1] * p.y + to_world[1][2] * p.z + to_world[1][3],
                to_world[2][0] * p.x + to_world[2][1] * p.y + to_world[2][2] * p.z + to_world[2][3]};
    }
    Vec3f VectorToWorld(const Vec3f& v) const {
        return {to_world[0][0] * v.x + to_world[0][1] * v.y + to_world[0][2] * v.z,
                to_world[1][0] * v.x + to_world[1][1] * v.y + to_world[1][2] * v.z,
                to_world[2][0] * v.x + to_world[2][1] * v.y + to_world[2][2] * v.z};
    }
};

struct Ray {
    Vec3f o, d;  // d unit
    float tmin = 0, tmax = kInf;
};

// Ray through the film position (fx, fy) in pixels; `lens` in [0,1)^2 is used when kDof
// (thin lens: every ray through the same film point meets at depth focus_distance).
template <bool kDof>
inline Ray GenerateCameraRay(const CameraModel& c, float fx, float fy, Point2<float> lens) {
    const float sx = (2 * fx / c.width - 1) * c.half_width + c.offset_x;
    const float sy = (1 - 2 * fy / c.height) * c.half_height + c.offset_y;
    Ray r;
    Vec3f o_cam, d_cam;
    if (c.orthographic) {
        o_cam = {sx, sy, 0};
        d_cam = {0, 0, -1};
    } else {
        d_cam = {sx, sy, -1};  // depth 1 along the view axis
        if constexpr (kDof) {
            const Point2<float> l = SampleUniformDiskConcentric(lens);
            o_cam = {l.u * c.aperture_radius, l.v * c.aperture_radius, 0};
            d_cam = d_cam * c.focus_distance - o_cam;
        }
    }
    // Clipping distances are depths along the view axis (as in Blender).
    const float len_cam = Length(d_cam);
    const float depth_per_unit = std::abs(d_cam.z) / len_cam;
    const Vec3f dw = c.VectorToWorld(d_cam);
    const float len_world = Length(dw);
    r.o = c.PointToWorld(o_cam);
    r.d = dw / len_world;
    const float scale = len_world / len_cam;  // world length of one camera-space unit
    r.tmin = c.clip_start * scale / depth_per_unit;
    r.tmax = c.clip_end >= 1e30f ? kInf : c.clip_end * scale / depth_per_unit;
    return r;
}

}  // namespace sphrect::render
