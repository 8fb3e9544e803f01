#include "screen_lights.h"

#include <algorithm>
#include <cmath>

#include "overlap_area.h"

namespace sphrect::render {
namespace {

struct V3 {
    double x, y, z;
};
V3 Sub(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
double Dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 Cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
V3 Scale(V3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
V3 D(const Vec3f& v) { return {v.x, v.y, v.z}; }

// The camera's world -> camera-space map (the inverse of CameraModel::to_world), and the camera-space
// -> film map: film (fx, fy) of the view-plane point (sx, sy) at depth 1 (perspective) or of the
// camera-space (sx, sy) (orthographic), inverting GenerateCameraRay's sx(fx), sy(fy).
struct CameraFrame {
    double inv[3][3];  // inverse of to_world's 3x3 part
    V3 origin;
    const CameraModel* c;

    explicit CameraFrame(const CameraModel& cam) : c(&cam) {
        const auto& m = cam.to_world;
        const double a = m[0][0], b = m[0][1], cc = m[0][2], d = m[1][0], e = m[1][1], f = m[1][2], g = m[2][0],
                     h = m[2][1], i = m[2][2];
        const double det = a * (e * i - f * h) - b * (d * i - f * g) + cc * (d * h - e * g);
        const double r = 1 / det;
        inv[0][0] = (e * i - f * h) * r;
        inv[0][1] = (cc * h - b * i) * r;
        inv[0][2] = (b * f - cc * e) * r;
        inv[1][0] = (f * g - d * i) * r;
        inv[1][1] = (a * i - cc * g) * r;
        inv[1][2] = (cc * d - a * f) * r;
        inv[2][0] = (d * h - e * g) * r;
        inv[2][1] = (b * g - a * h) * r;
        inv[2][2] = (a * e - b * d) * r;
        origin = {m[0][3], m[1][3], m[2][3]};
    }
    bool Valid() const { return std::isfinite(inv[0][0] + inv[1][1] + inv[2][2]); }
    V3 VectorToCamera(V3 v) const {
        return {inv[0][0] * v.x + inv[0][1] * v.y + inv[0][2] * v.z,
                inv[1][0] * v.x + inv[1][1] * v.y + inv[1][2] * v.z,
                inv[2][0] * v.x + inv[2][1] * v.y + inv[2][2] * v.z};
    }
    V3 PointToCamera(V3 p) const { return VectorToCamera(Sub(p, origin)); }
    // Film coordinates from the view-plane coordinates (sx, sy).
    double FilmX(double sx) const { return ((sx - c->offset_x) / c->half_width + 1) * 0.5 * c->width; }
    double FilmY(double sy) const { return (1 - (sy - c->offset_y) / c->half_height) * 0.5 * c->height; }
    // The affine map film (fx, fy, 1) -> view-plane (sx, sy): rows of a 3x3 whose last row is (0, 0, 1).
    void FilmToView(double k[3][3]) const {
        k[0][0] = 2.0 * c->half_width / c->width;
        k[0][1] = 0;
        k[0][2] = c->offset_x - c->half_width;
        k[1][0] = 0;
        k[1][1] = -2.0 * c->half_height / c->height;
        k[1][2] = c->half_height + c->offset_y;
        k[2][0] = 0;
        k[2][1] = 0;
        k[2][2] = 1;
    }
};

// Film point of the camera-space point q (in front of the camera).
void ToFilm(const CameraFrame& f, V3 q, double* x, double* y) {
    const double sx = f.c->orthographic ? q.x : q.x / -q.z, sy = f.c->orthographic ? q.y : q.y / -q.z;
    *x = f.FilmX(sx);
    *y = f.FilmY(sy);
}

// Depth range [lo, hi] is strictly inside the clipping range (with a margin for the rays' rounding).
bool WithinClipping(const CameraModel& c, double lo, double hi) {
    constexpr double kMargin = 1e-4;
    return lo > c.clip_start * (1 + kMargin) + kMargin * 1e-3 && hi < double(c.clip_end) * (1 - kMargin);
}

bool FinishBox(ScreenLight& s, const double* x, const double* y, int n) {
    s.x0 = s.x1 = x[0];
    s.y0 = s.y1 = y[0];
    for (int i = 1; i < n; ++i) {
        s.x0 = std::min(s.x0, x[i]);
        s.x1 = std::max(s.x1, x[i]);
        s.y0 = std::min(s.y0, y[i]);
        s.y1 = std::max(s.y1, y[i]);
    }
    return std::isfinite(s.x0 + s.x1 + s.y0 + s.y1);
}

bool MakeRectangleImage(const CameraFrame& f, const AreaLight& l, ScreenLight& s) {
    const V3 c0 = D(l.frame.light.corner), ex = D(l.frame.light.ex), ey = D(l.frame.light.ey);
    const V3 corners[4] = {c0,
                           {c0.x + ex.x, c0.y + ex.y, c0.z + ex.z},
                           {c0.x + ex.x + ey.x, c0.y + ex.y + ey.y, c0.z + ex.z + ey.z},
                           {c0.x + ey.x, c0.y + ey.y, c0.z + ey.z}};
    double lo = INFINITY, hi = -INFINITY;
    for (int k = 0; k < 4; ++k) {
        const V3 q = f.PointToCamera(corners[k]);
        lo = std::min(lo, -q.z);
        hi = std::max(hi, -q.z);
        ToFilm(f, q, &s.qx[k], &s.qy[k]);
    }
    if (!WithinClipping(*f.c, lo, hi)) return false;
    double area2 = 0;
    for (int k = 0; k < 4; ++k) area2 += s.qx[k] * s.qy[(k + 1) & 3] - s.qx[(k + 1) & 3] * s.qy[k];
    if (!(std::abs(area2) > 1e-12)) return false;  // seen edge-on
    if (area2 < 0) {
        std::swap(s.qx[1], s.qx[3]);
        std::swap(s.qy[1], s.qy[3]);
    }
    return FinishBox(s, s.qx, s.qy, 4);
}

// The image of the ellipse {C + a A + b B : a^2 + b^2 <= 1} (camera space) is the film conic
// (H s)^T diag(1, 1, -1) (H s) <= 0, s = (fx, fy, 1), where H maps a film point to the homogeneous
// plane coordinates (a, b, w) of the point its ray meets.  Perspective, ray t d from the eye with
// d = (sx, sy, -1): t = N.C / N.d, so (a, b, w) ~ ((N.C) A - (C.A) N, (N.C) B - (C.B) N, N) . d
// over |A|^2, |B|^2, 1.  Orthographic, ray o + t d0 with o = (sx, sy, 0), d0 = (0, 0, -1): the same
// numerators with d -> (N.d0) o - (d0.o) ... worked out below, and w = 1.
bool MakeEllipseImage(const CameraFrame& f, const AreaLight& l, ScreenLight& s) {
    const V3 C = f.PointToCamera(D(l.center)), A = f.VectorToCamera(D(l.ax)), B = f.VectorToCamera(D(l.ay));
    const double dz = std::sqrt(A.z * A.z + B.z * B.z);
    if (!WithinClipping(*f.c, -C.z - dz, -C.z + dz)) return false;
    const V3 N = Cross(A, B);
    const double aa = Dot(A, A), bb = Dot(B, B);
    double k[3][3];
    f.FilmToView(k);
    // rows[r] acts on (sx, sy, 1) (perspective: on d = (sx, sy, -1); orthographic: on o and a constant).
    double rows[3][3];
    if (!f.c->orthographic) {
        const double nc = Dot(N, C);
        const V3 ra = Scale(Sub(Scale(A, nc), Scale(N, Dot(C, A))), 1 / aa);
        const V3 rb = Scale(Sub(Scale(B, nc), Scale(N, Dot(C, B))), 1 / bb);
        const V3 r[3] = {ra, rb, N};
        for (int i = 0; i < 3; ++i) {  // r . (sx, sy, -1)
            rows[i][0] = r[i].x;
            rows[i][1] = r[i].y;
            rows[i][2] = -r[i].z;
        }
    } else {
        // a |A|^2 (N.d0) = (N.d0) A.o - (d0.A) N.o + (N.C)(d0.A) - (C.A)(N.d0), o = (sx, sy, 0), d0 = -z.
        const double nd = -N.z;
        if (!(std::abs(nd) > 0)) return false;
        auto row = [&](V3 X, double xx, double* out) {
            const double dx = -X.z;
            out[0] = (nd * X.x - dx * N.x) / (xx * nd);
            out[1] = (nd * X.y - dx * N.y) / (xx * nd);
            out[2] = (Dot(N, C) * dx - Dot(C, X) * nd) / (xx * nd);
        };
        row(A, aa, rows[0]);
        row(B, bb, rows[1]);
        rows[2][0] = 0;
        rows[2][1] = 0;
        rows[2][2] = 1;
    }
    // H = rows . k, then rescaled (the conic does not change) so that its entries are O(1).
    double H[3][3], big = 0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            H[i][j] = rows[i][0] * k[0][j] + rows[i][1] * k[1][j] + rows[i][2] * k[2][j];
            big = std::max(big, std::abs(H[i][j]));
        }
    if (!(big > 0) || !std::isfinite(big)) return false;
    for (auto& r : H)
        for (double& v : r) v /= big;
    double Q[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) Q[i][j] = H[0][i] * H[0][j] + H[1][i] * H[1][j] - H[2][i] * H[2][j];
    const double det2 = Q[0][0] * Q[1][1] - Q[0][1] * Q[0][1];
    if (!(Q[0][0] > 0 && det2 > 0)) return false;  // not an ellipse on the film
    // Centre c = -Q2^{-1} q, value there F(c) = Q22 + q . c < 0.
    s.cx = -(Q[1][1] * Q[0][2] - Q[0][1] * Q[1][2]) / det2;
    s.cy = -(Q[0][0] * Q[1][2] - Q[0][1] * Q[0][2]) / det2;
    const double fc = Q[2][2] + Q[0][2] * s.cx + Q[1][2] * s.cy;
    if (!(fc < 0)) return false;
    s.m00 = Q[0][0] / -fc;
    s.m01 = Q[0][1] / -fc;
    s.m11 = Q[1][1] / -fc;
    s.l00 = std::sqrt(s.m00);
    s.l01 = s.m01 / s.l00;
    s.l11 = std::sqrt(std::max(s.m11 - s.l01 * s.l01, 0.0));
    if (!(s.l11 > 0)) return false;
    // Half-extents of the ellipse: sqrt of the diagonal of M^{-1}.
    const double det = s.m00 * s.m11 - s.m01 * s.m01;
    const double hx = std::sqrt(s.m11 / det), hy = std::sqrt(s.m00 / det);
    const double bx[2] = {s.cx - hx, s.cx + hx}, by[2] = {s.cy - hy, s.cy + hy};
    s.ellipse = true;
    return FinishBox(s, bx, by, 2);
}

}  // namespace

std::vector<ScreenLight> BuildScreenLights(const CameraModel& camera, const std::vector<AreaLight>& lights,
                                           size_t count) {
    std::vector<ScreenLight> out;
    const CameraFrame frame(camera);
    if (camera.aperture_radius > 0 && !camera.orthographic) return out;  // depth of field blurs the image
    if (!frame.Valid()) return out;
    const V3 view_dir = {camera.to_world[0][2], camera.to_world[1][2], camera.to_world[2][2]};  // camera +Z
    for (size_t i = 0; i < std::min(count, lights.size()); ++i) {
        const AreaLight& l = lights[i];
        // A light with spread or a texture is not seen uniformly (its radiance varies over its image): camera rays see
        // it.
        if (!l.visible || l.on_mesh || l.shape == AreaShape::Triangle || l.HasSpread() || l.texture >= 0) continue;
        // Towards the camera, from the light: the eye (perspective) or the view direction reversed
        // (orthographic, whose rays are parallel): one side of the light for the whole image.
        const V3 toward = camera.orthographic ? view_dir : Sub(frame.origin, D(l.center));
        const Vec3f toward_f{float(toward.x), float(toward.y), float(toward.z)};
        const double side = Dot(D(l.n), toward);
        if (!(std::abs(side) > 1e-6 * std::sqrt(Dot(toward, toward)))) continue;  // edge-on
        ScreenLight s;
        s.light = int(i);
        s.radiance = EmittedRadiance(l, toward_f);
        if (IsBlack(s.radiance)) continue;
        const bool ok =
            l.shape == AreaShape::Rectangle ? MakeRectangleImage(frame, l, s) : MakeEllipseImage(frame, l, s);
        // Lights wholly off the film need nothing.
        if (ok && s.x1 > 0 && s.y1 > 0 && s.x0 < camera.width && s.y0 < camera.height) out.push_back(s);
    }
    return out;
}

double BoxCoverage(const ScreenLight& s, double x0, double y0, double x1, double y1) {
    if (s.x1 <= x0 || s.x0 >= x1 || s.y1 <= y0 || s.y0 >= y1) return 0;
    if (InsideScreenLight(s, x0, y0) && InsideScreenLight(s, x1, y0) && InsideScreenLight(s, x0, y1) &&
        InsideScreenLight(s, x1, y1))
        return 1;  // a convex image holding the square's corners holds the square
    const double box_area = (x1 - x0) * (y1 - y0);
    if (!s.ellipse) return std::min(ConvexPolygonBoxArea(s.qx, s.qy, 4, x0, y0, x1, y1) / box_area, 1.0);
    // The pixel's corners in the disk's frame z = L (p - c), where the area scales by det L.
    double zx[4], zy[4];
    const double cx[4] = {x0, x1, x1, x0}, cy[4] = {y0, y0, y1, y1};
    for (int k = 0; k < 4; ++k) {
        const double dx = cx[k] - s.cx, dy = cy[k] - s.cy;
        zx[k] = s.l00 * dx + s.l01 * dy;
        zy[k] = s.l11 * dy;
    }
    const double area = std::abs(UnitDiskPolygonArea(zx, zy, 4)) / (s.l00 * s.l11);
    return std::clamp(area / box_area, 0.0, 1.0);
}

double PixelCoverage(const ScreenLight& s, int px, int py) { return BoxCoverage(s, px, py, px + 1.0, py + 1.0); }

}  // namespace sphrect::render
