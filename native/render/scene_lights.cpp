// The scene's lights as Blender defines them (Cycles: scene/light.cpp): rectangles, ellipses, points, spots and
// suns, checked; area lights that cannot emit are skipped with the reason.
#include <cmath>
#include <limits>
#include <string>

#include "scene.h"
#include "scene_checks.h"

namespace sphrect::render {

namespace {

// Why an area light of this area is skipped ("" if it is not).
std::string SkippedForArea(const std::string& what, float area) {
    if (!(area > 0)) return what + " with zero area skipped";
    if (!std::isfinite(area)) return what + " whose area overflows float skipped";
    return {};
}

// An area light's spread: radians in [0, pi] (Blender's range; pi: none).
void CheckSpread(const std::string& what, float spread) {
    if (!(spread >= 0 && spread <= kPi)) Fail(what + " spread must be in [0, pi] radians");
}

}  // namespace

std::string RenderScene::AddRectLight(const Vec3f& corner, const Vec3f& ex, const Vec3f& ey, const Spectrum& radiance,
                                      bool two_sided, bool visible, float spread, const LightVisibility& vis) {
    RequireNotCommitted();
    CheckColor("rectangle light radiance", radiance);
    CheckSpread("rectangle light", spread);
    const std::string problem = ValidateRectLight(RectLight<float>{corner, ex, ey, two_sided});
    if (!problem.empty()) Fail(problem);
    const std::string skipped = SkippedForArea("rectangle light", Length(Cross(ex, ey)));
    if (!skipped.empty()) return skipped;
    if (IsBlack(radiance)) return "rectangle light with zero radiance skipped";
    area_lights.push_back(MakeRectAreaLight(corner, ex, ey, radiance, two_sided, visible));
    SetAreaSpread(area_lights.back(), spread);
    area_lights.back().vis = vis;
    return {};
}

std::string RenderScene::AddEllipseLight(const Vec3f& center, const Vec3f& ax, const Vec3f& ay,
                                         const Spectrum& radiance, bool two_sided, bool visible, float spread,
                                         const LightVisibility& vis) {
    RequireNotCommitted();
    CheckColor("ellipse light radiance", radiance);
    CheckSpread("ellipse light", spread);
    CheckVector("ellipse light centre", center);
    CheckVector("ellipse light axes", ax);
    CheckVector("ellipse light axes", ay);
    const float la = Length(ax), lb = Length(ay);
    if (la > 0 && lb > 0 && std::abs(Dot(ax, ay)) > 1e-4f * la * lb)
        Fail("ellipse light axes axis_x and axis_y must be orthogonal");
    const std::string skipped = SkippedForArea("ellipse light", Length(Cross(ax, ay)));
    if (!skipped.empty()) return skipped;
    if (IsBlack(radiance)) return "ellipse light with zero radiance skipped";
    area_lights.push_back(MakeEllipseAreaLight(center, ax, ay, radiance, two_sided, visible));
    SetAreaSpread(area_lights.back(), spread);
    area_lights.back().vis = vis;
    return {};
}

// A point or spot light's radius: finite, >= 0, and 0 or large enough that pi r^2 stays a normal float.
static void CheckLightRadius(const char* what, float radius) {
    if (!(radius >= 0 && std::isfinite(radius)))
        Fail(std::string(what) + " radius must be finite and >= 0, got " + std::to_string(radius));
    if (radius > 0 && !(kPi * radius * radius >= std::numeric_limits<float>::min()))
        Fail(std::string(what) + " radius must be 0 or at least 1e-18");
}

void RenderScene::AddPointLight(const Vec3f& position, const Spectrum& intensity, float radius, bool visible,
                                const LightVisibility& vis) {
    RequireNotCommitted();
    CheckVector("point light position", position);
    CheckColor("point light intensity", intensity);
    CheckLightRadius("point light", radius);
    DeltaLight l;
    l.kind = DeltaKind::Point;
    l.position = position;
    l.power = intensity;
    l.radius = radius;
    l.visible = visible;
    l.vis = vis;
    delta_lights.push_back(l);
}

void RenderScene::AddSpotLight(const Vec3f& position, const Vec3f& direction, const Spectrum& intensity,
                               float spot_size, float spot_blend, float radius, bool visible,
                               const LightVisibility& vis) {
    RequireNotCommitted();
    CheckVector("spot light position", position);
    CheckColor("spot light intensity", intensity);
    CheckLightRadius("spot light", radius);
    if (!IsFinite(direction) || !(Length(direction) > 0)) Fail("spot light direction must be a non-zero vector");
    if (!(spot_size > 0 && spot_size <= 2 * kPi)) Fail("spot_size must be in (0, 2 pi]");
    if (!(spot_blend >= 0 && spot_blend <= 1)) Fail("spot_blend must be in [0, 1]");
    DeltaLight l;
    l.kind = DeltaKind::Spot;
    l.position = position;
    l.axis = Normalize(direction);
    l.power = intensity;
    l.cos_half_angle = std::cos(std::min(spot_size, kPi) / 2);
    l.spot_smooth = (1 - l.cos_half_angle) * spot_blend;
    l.radius = radius;
    l.visible = visible;
    l.vis = vis;
    delta_lights.push_back(l);
}

void RenderScene::AddSunLight(const Vec3f& direction, const Spectrum& irradiance, float angle, bool visible,
                              const LightVisibility& vis) {
    RequireNotCommitted();
    CheckColor("sun irradiance", irradiance);
    if (!IsFinite(direction) || !(Length(direction) > 0)) Fail("sun direction must be a non-zero vector");
    if (!(angle >= 0 && angle <= kPi)) Fail("sun angle must be in [0, pi], got " + std::to_string(angle));
    DeltaLight l;
    l.kind = DeltaKind::Sun;
    l.axis = -Normalize(direction);  // towards the sun
    l.power = irradiance;
    // 1 - cos(angle / 2) = 2 sin^2(angle / 4), in double: exact for a 1e-4 rad sun.
    const double s = std::sin(double(angle) / 4);
    l.sun_one_minus_cos = float(2 * s * s);
    l.visible = visible;
    l.vis = vis;
    delta_lights.push_back(l);
}

}  // namespace sphrect::render
