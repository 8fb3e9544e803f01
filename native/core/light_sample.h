// What every light-sampling technique returns for one (u, v).
#pragma once

#include "vec3.h"

namespace sphrect {

template <class T>
struct LightSample {
    Vec3<T> point;  // on the light
    Vec3<T> dir;    // unit vector from the shading point towards `point`
    T dist = 0;     // |point - origin|
    T pdf = 0;      // w.r.t. solid angle at the shading point; 0 marks an invalid sample

    bool Valid() const { return pdf > 0; }
};

}  // namespace sphrect
