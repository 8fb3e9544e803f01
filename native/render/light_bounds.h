// What the light tree (light_tree.h) knows of one emitter; each emitter type computes its own
// (area_light.h, delta_light.h), as pbrt-v4's Light::Bounds().
#pragma once

#include "sampling_util.h"

namespace sphrect::render {

// One emitter as the tree sees it.  The orientation cone (Conty Estevez & Kulla, sec. 4.1):
// every direction of emission lies within theta_o of `axis`, and the emission falls to zero
// within a further theta_e (cosine falloff over it); two_sided: also the mirrored cone around
// -axis.  A one-sided planar light: (n, cos_theta_o = 1, cos_theta_e = 0); a point light
// covers the sphere (cos_theta_o = -1); a spot light its cone (cos_theta_o = cos(half angle),
// cos_theta_e = 1: nothing outside it).
struct LightBounds {
    Vec3f lo, hi;         // world bounds (lo <= hi; a point light has lo == hi)
    double power = 0;     // its largest radiant intensity (luminance): L*A for an area light (per
                          // side), I for a point or spot; power * cos / d^2 estimates irradiance
    Vec3f axis{0, 0, 1};  // unit; ignored when cos_theta_o <= -1
    float cos_theta_o = 1;
    float cos_theta_e = 0;
    bool two_sided = false;
};

}  // namespace sphrect::render
