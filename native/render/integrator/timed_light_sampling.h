// LightSamplingAt with its time counted: the stats' light_time (thread-seconds in light
// sampling: the light choice, sampler setup, Sample, PDF) is the sum of these calls' ticks, so the shading code
// that calls them carries no timing of its own.
#pragma once

#include <cstdint>

#include "light_sampling_at.h"
#include "render/ticks.h"

namespace sphrect::render {

template <Technique K>
class TimedLightSamplingAt {
  public:
    TimedLightSamplingAt(const RenderScene& scene, LightSelection selection, const Vec3f& origin, const Vec3f& normal,
                         const Vec3f& tree_normal, int light_samples, EllipseTechnique ellipse_technique,
                         uint64_t& ticks, bool emission_blocks = true)
        : sampling_(scene, selection, origin, normal, tree_normal, light_samples, ellipse_technique, emission_blocks),
          ticks_(ticks) {}

    void FollowGlossyLobe(const GlossyLobe<float>& lobe) { sampling_.FollowGlossyLobe(lobe); }

    ChosenLight Choose(Point2<float> light_point) {
        const uint64_t t0 = ReadTicks();
        const ChosenLight light = sampling_.Choose(light_point);
        ticks_ += ReadTicks() - t0;
        return light;
    }

    LightSample<float> Sample(int index, Point2<float> u) {
        const uint64_t t0 = ReadTicks();
        const LightSample<float> ls = sampling_.Sample(index, u);
        ticks_ += ReadTicks() - t0;
        return ls;
    }

    float PDF(int index, const Vec3f& p) {
        const uint64_t t0 = ReadTicks();
        const float pdf = sampling_.PDF(index, p);
        ticks_ += ReadTicks() - t0;
        return pdf;
    }

    float SoftLightPDF(const DeltaLight& l, int tree_emitter) {
        const uint64_t t0 = ReadTicks();
        const float pdf = sampling_.SoftLightPDF(l, tree_emitter);
        ticks_ += ReadTicks() - t0;
        return pdf;
    }

  private:
    LightSamplingAt<K> sampling_;
    uint64_t& ticks_;
};

}  // namespace sphrect::render
