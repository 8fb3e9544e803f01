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

// The compact ray differential (Cycles 3.4's sd->dP: a radius, differential_transfer_compact) at the hit of a camera
// ray at distance t from its origin along unit world direction d.  Orthographic: the world length of one pixel's step
// across the film (Cycles' camera_sample_orthographic takes the x step for both axes), constant.  Perspective: t times
// dD = the mean length of the change of the unit direction over one pixel's step in x and in y on the film (the
// pinhole's direction through the film point d points at, as camera_sample_perspective computes it also with depth of
// field); the near-clip part of Cycles' ray dP and the rest of the way add up to the whole distance t.
inline float CameraFootprint(const CameraModel& c, const Vec3f& d, float t) {
    const Vec3f step_x = c.VectorToWorld({2 * c.half_width / float(c.width), 0, 0});
    if (c.orthographic) return Length(step_x);
    const Vec3f step_y = c.VectorToWorld({0, 2 * c.half_height / float(c.height), 0});
    // d in the camera's frame (the inverse of to_world's linear part: its columns' cross products over det).
    const Vec3f a(c.to_world[0][0], c.to_world[1][0], c.to_world[2][0]);
    const Vec3f b(c.to_world[0][1], c.to_world[1][1], c.to_world[2][1]);
    const Vec3f e(c.to_world[0][2], c.to_world[1][2], c.to_world[2][2]);
    const float det = Dot(a, Cross(b, e));
    const float depth = -Dot(d, Cross(a, b)) / det;  // d's camera-space z is -depth
    if (!(depth > 0)) return 0;
    const Vec3f center = d / depth;  // the film point at camera depth 1, from the eye
    const Vec3f unit = Normalize(center);
    const float dD = 0.5f * (Length(Normalize(center + step_x) - unit) + Length(Normalize(center + step_y) - unit));
    return t * dD;
}

}  // namespace sphrect::render
