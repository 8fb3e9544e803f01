// The textbook single-precision formulation of the spherical-rectangle map: the
// paper's (Urena, Fajardo & King 2013) algorithm evaluated as published, in float,
// with Omega = g0 + g1 + g2 + g3 - 2 pi from the four corner angles (as in
// Blender 3.4 Cycles).  Only a baseline for the benchmark and the study's accuracy
// table; it is not a technique (rectangle.h is the robust one;
// docs/rectangle_map.md maps its variables to these).
#pragma once

#include <algorithm>
#include <cmath>

#include "light_sample.h"
#include "rect_light.h"

namespace sphrect {

struct TextbookRectangle {
    Vec3f o, x, y, z;
    float z0 = 0, z0sq = 0, x0 = 0, y0 = 0, y0sq = 0, x1 = 0, y1 = 0, y1sq = 0;
    float b0 = 0, b1 = 0, b0sq = 0, k = 0, S = 0;  // S: the solid angle
};

inline TextbookRectangle MakeTextbookRectangle(const Vec3f& o, const RectLight<float>& light) {
    TextbookRectangle q;
    const float exl = Length(light.ex), eyl = Length(light.ey);
    q.o = o;
    q.x = light.ex / exl;
    q.y = light.ey / eyl;
    q.z = Cross(q.x, q.y);
    const Vec3f d = light.corner - o;
    q.z0 = Dot(d, q.z);
    if (q.z0 > 0) {  // flip z so that the rectangle is at z0 < 0
        q.z = -q.z;
        q.z0 = -q.z0;
    }
    q.z0sq = q.z0 * q.z0;
    q.x0 = Dot(d, q.x);
    q.y0 = Dot(d, q.y);
    q.x1 = q.x0 + exl;
    q.y1 = q.y0 + eyl;
    q.y0sq = q.y0 * q.y0;
    q.y1sq = q.y1 * q.y1;
    const Vec3f v00(q.x0, q.y0, q.z0), v01(q.x0, q.y1, q.z0), v10(q.x1, q.y0, q.z0), v11(q.x1, q.y1, q.z0);
    const Vec3f n0 = Normalize(Cross(v00, v10)), n1 = Normalize(Cross(v10, v11));
    const Vec3f n2 = Normalize(Cross(v11, v01)), n3 = Normalize(Cross(v01, v00));
    auto safe_acos = [](float c) { return std::acos(std::min(std::max(c, -1.f), 1.f)); };
    const float g0 = safe_acos(-Dot(n0, n1)), g1 = safe_acos(-Dot(n1, n2));
    const float g2 = safe_acos(-Dot(n2, n3)), g3 = safe_acos(-Dot(n3, n0));
    q.b0 = n0.z;
    q.b1 = n2.z;
    q.b0sq = q.b0 * q.b0;
    q.k = 2 * float(M_PI) - g2 - g3;
    q.S = g0 + g1 - q.k;
    return q;
}

inline LightSample<float> SampleTextbookRectangle(const TextbookRectangle& q, float u, float v) {
    const float au = u * q.S + q.k;
    const float fu = (std::cos(au) * q.b0 - q.b1) / std::sin(au);
    float cu = 1 / std::sqrt(fu * fu + q.b0sq) * (fu > 0 ? 1.f : -1.f);
    cu = std::min(std::max(cu, -1.f), 1.f);
    float xu = -(cu * q.z0) / std::sqrt(1 - cu * cu);
    xu = std::min(std::max(xu, q.x0), q.x1);
    const float d = std::sqrt(xu * xu + q.z0sq);
    const float h0 = q.y0 / std::sqrt(d * d + q.y0sq), h1 = q.y1 / std::sqrt(d * d + q.y1sq);
    const float hv = h0 + v * (h1 - h0), hv2 = hv * hv;
    const float yv = hv2 < 1 - 1e-6f ? hv * d / std::sqrt(1 - hv2) : q.y1;
    LightSample<float> s;
    const Vec3f w = q.x * xu + q.y * yv + q.z * q.z0;
    s.point = q.o + w;
    s.dist = Length(w);
    s.dir = w / s.dist;
    s.pdf = 1 / q.S;
    return s;
}

}  // namespace sphrect
