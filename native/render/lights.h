// Emitters of the renderer.
//
// Area lights (rectangles and ellipses/discs, area_light.h) are sampled and intersected
// analytically; they are not Embree geometry and do not occlude each other or the scene (as in
// Cycles, where light objects are transparent to rays).  One is chosen per light sample by power
// (light_selector.h).  Point, spot and sun lights (delta_light.h) are evaluated once per camera
// sample with a shadow ray (no MIS possible); with a radius or an angle they are soft, sampled by
// the cone they subtend with MIS against the BSDF rays that reach them.
#pragma once

#include "area_light.h"
#include "delta_light.h"
#include "light_selector.h"
