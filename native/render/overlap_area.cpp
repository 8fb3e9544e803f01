#include "overlap_area.h"

#include <algorithm>
#include <cmath>

namespace sphrect::render {
namespace {

// Signed area of the unit disk inside the triangle (origin, p, q).
double DiskTriangleArea(double px, double py, double qx, double qy) {
    auto sector = [](double ax, double ay, double bx, double by) {
        return 0.5 * std::atan2(ax * by - ay * bx, ax * bx + ay * by);
    };
    const double dx = qx - px, dy = qy - py;
    const double a = dx * dx + dy * dy, b = px * dx + py * dy, c = px * px + py * py - 1;
    if (!(a > 0)) return 0;
    const double disc = b * b - a * c;
    if (disc <= 0) return sector(px, py, qx, qy);  // the edge's line misses the disk
    const double root = std::sqrt(disc);
    const double t0 = std::max((-b - root) / a, 0.0), t1 = std::min((-b + root) / a, 1.0);
    if (t0 >= t1) return sector(px, py, qx, qy);  // the segment is outside
    const double ax = px + t0 * dx, ay = py + t0 * dy, bx = px + t1 * dx, by = py + t1 * dy;
    return sector(px, py, ax, ay) + 0.5 * (ax * by - ay * bx) + sector(bx, by, qx, qy);
}

}  // namespace

double ConvexPolygonBoxArea(const double* x, const double* y, int n, double bx0, double by0, double bx1, double by1) {
    constexpr int kMax = 16;  // n <= 8, plus one vertex per clipping side
    double ax[kMax], ay[kMax], cx[kMax], cy[kMax];
    int m = std::min(n, 8);
    std::copy(x, x + m, ax);
    std::copy(y, y + m, ay);
    // Keeps the part with s * (coordinate - bound) >= 0.
    auto clip = [&](int axis, double bound, double sgn) {
        int k = 0;
        for (int i = 0; i < m; ++i) {
            const int j = (i + 1) % m;
            const double pi = sgn * ((axis == 0 ? ax[i] : ay[i]) - bound),
                         pj = sgn * ((axis == 0 ? ax[j] : ay[j]) - bound);
            if (pi >= 0) {
                cx[k] = ax[i];
                cy[k] = ay[i];
                ++k;
            }
            if ((pi < 0) != (pj < 0) && pi != 0 && pj != 0) {
                const double t = pi / (pi - pj);
                cx[k] = ax[i] + t * (ax[j] - ax[i]);
                cy[k] = ay[i] + t * (ay[j] - ay[i]);
                if (axis == 0)
                    cx[k] = bound;
                else
                    cy[k] = bound;
                ++k;
            }
        }
        m = k;
        std::copy(cx, cx + m, ax);
        std::copy(cy, cy + m, ay);
    };
    clip(0, bx0, 1);
    if (m) clip(0, bx1, -1);
    if (m) clip(1, by0, 1);
    if (m) clip(1, by1, -1);
    double area2 = 0;
    for (int i = 0; i < m; ++i) area2 += ax[i] * ay[(i + 1) % m] - ax[(i + 1) % m] * ay[i];
    return 0.5 * std::abs(area2);
}

double UnitDiskPolygonArea(const double* x, const double* y, int n) {
    double area = 0;
    for (int i = 0; i < n; ++i) {
        const int j = (i + 1) % n;
        area += DiskTriangleArea(x[i], y[i], x[j], y[j]);
    }
    return area;
}

}  // namespace sphrect::render
