// The analytic lights the camera sees, as exact shapes in film coordinates, for a control variate
// of the pixels they partly cover (integrator/light_coverage.h).
//
// Why: where a scene's error is in the pixels that see a bright light (the edges of softboxes and
// disks), the estimate of how much of a pixel the light covers is the noise, and no light sampling
// changes it.  With a box pixel filter and a pinhole or orthographic camera the light's image is
// a convex quadrilateral (a rectangle) or an ellipse (a disk or ellipse), whose overlap with the
// pixel square has a closed form.  So the integrator estimates
//     pixel = E[f(x) - g(x)] + integral of g over the pixel,   g(x) = L [x inside the light's image],
// which is unbiased for any g whose integral is exact, and whose variance is that of f - g: zero
// where the camera ray does see the light, f itself where it does not.  Where an object in front
// hides part of the light, a grid of cheap rays estimates the share it leaves seen
// (integrator/light_coverage.h); what is left is the light's shading of what surrounds it.
//
// Coordinates: film pixels (x right, y down), the convention of GenerateCameraRay.
#pragma once

#include <cstddef>
#include <vector>

#include "area_light.h"
#include "camera.h"

namespace sphrect::render {

struct ScreenLight {
    int light = -1;     // index in RenderScene::area_lights
    Spectrum radiance;  // what a camera ray crossing it sees (the same everywhere on the light)
    bool ellipse = false;
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // film bounding box
    // Rectangle: the image's corners, ordered so that their shoelace area is positive.
    double qx[4] = {}, qy[4] = {};
    // Ellipse: the image is (p - c)^T M (p - c) <= 1, with M = L^T L, L = [[l00, l01], [0, l11]].
    double cx = 0, cy = 0, m00 = 0, m01 = 0, m11 = 0, l00 = 0, l01 = 0, l11 = 0;
};

// The lights [0, count) of `lights` that get a screen shape: seen by camera rays (visible, not on
// a mesh), with radiance towards the camera, wholly between the clipping planes and in front of a
// camera without depth of field.  Lights the camera sees edge-on, or whose image is degenerate,
// are left out (they keep the sampled estimate).
std::vector<ScreenLight> BuildScreenLights(const CameraModel& camera, const std::vector<AreaLight>& lights,
                                           size_t count);

// Whether film point (x, y) is inside s's image.
inline bool InsideScreenLight(const ScreenLight& s, double x, double y) {
    if (s.ellipse) {
        const double dx = x - s.cx, dy = y - s.cy;
        return s.m00 * dx * dx + 2 * s.m01 * dx * dy + s.m11 * dy * dy <= 1;
    }
    for (int k = 0; k < 4; ++k) {
        const int j = (k + 1) & 3;
        if ((s.qx[j] - s.qx[k]) * (y - s.qy[k]) - (s.qy[j] - s.qy[k]) * (x - s.qx[k]) < 0) return false;
    }
    return true;
}

// Fraction of the box [x0, x1) x [y0, y1) inside s's image, in [0, 1].
double BoxCoverage(const ScreenLight& s, double x0, double y0, double x1, double y1);
// Fraction of the pixel [px, px + 1) x [py, py + 1) inside s's image, in [0, 1].
double PixelCoverage(const ScreenLight& s, int px, int py);

}  // namespace sphrect::render
