// The small vector types of the sampling core and the renderer: Vec3 and Point2.
// Templated on the scalar so every technique exists in float (the renderer's
// path) and double (the reference path used by tests and benchmarks).
#pragma once

#include <cmath>

namespace sphrect {

// Clamp to [lo, hi] that maps NaN to lo.
inline double ClampNaN(double x, double lo, double hi) { return x > lo ? (x < hi ? x : hi) : lo; }

template <class T>
struct Vec3 {
    T x = 0, y = 0, z = 0;

    constexpr Vec3() = default;
    constexpr Vec3(T x_, T y_, T z_) : x(x_), y(y_), z(z_) {}
    template <class U>
    constexpr explicit Vec3(const Vec3<U>& o) : x(T(o.x)), y(T(o.y)), z(T(o.z)) {}

    constexpr T operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    constexpr Vec3 operator+(const Vec3& o) const { return {x + o.x, y + o.y, z + o.z}; }
    constexpr Vec3 operator-(const Vec3& o) const { return {x - o.x, y - o.y, z - o.z}; }
    constexpr Vec3 operator-() const { return {-x, -y, -z}; }
    constexpr Vec3 operator*(T s) const { return {x * s, y * s, z * s}; }
    constexpr Vec3 operator/(T s) const { return {x / s, y / s, z / s}; }
    constexpr Vec3 operator*(const Vec3& o) const { return {x * o.x, y * o.y, z * o.z}; }
    Vec3& operator+=(const Vec3& o) {
        x += o.x;
        y += o.y;
        z += o.z;
        return *this;
    }
    Vec3& operator-=(const Vec3& o) {
        x -= o.x;
        y -= o.y;
        z -= o.z;
        return *this;
    }
    Vec3& operator*=(T s) {
        x *= s;
        y *= s;
        z *= s;
        return *this;
    }
};

template <class T>
constexpr Vec3<T> operator*(T s, const Vec3<T>& v) {
    return v * s;
}
template <class T>
constexpr T Dot(const Vec3<T>& a, const Vec3<T>& b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class T>
constexpr Vec3<T> Cross(const Vec3<T>& a, const Vec3<T>& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class T>
inline T Length(const Vec3<T>& v) {
    return std::sqrt(Dot(v, v));
}
template <class T>
inline Vec3<T> Normalize(const Vec3<T>& v) {
    return v / Length(v);
}
// Tangent t and bitangent b completing the unit vector z to an orthonormal basis (Duff et al. 2017's branchless one).
template <class T>
inline void BranchlessTangents(const Vec3<T>& z, Vec3<T>& t, Vec3<T>& b) {
    const T sign = std::copysign(T(1), z.z), a = -1 / (sign + z.z), xy = z.x * z.y * a;
    t = Vec3<T>(1 + sign * z.x * z.x * a, sign * xy, -sign * z.x);
    b = Vec3<T>(xy, sign + z.y * z.y * a, -z.y);
}
template <class T>
inline bool IsFinite(const Vec3<T>& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

using Vec3f = Vec3<float>;
using Vec3d = Vec3<double>;

// A point of [0,1]^2: the (u, v) a technique maps, or a 2D sample.
template <class T>
struct Point2 {
    T u = 0, v = 0;
};

}  // namespace sphrect
