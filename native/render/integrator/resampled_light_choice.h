// Light selection "ris": resampled importance sampling of a light sample (Talbot et al. 2005; the per-pixel part of
// Bitterli et al. 2020).  M = RenderOptions::ris_candidates candidates x_i are drawn as "tree" draws its light sample
// (the tree's emitter at the receiver, then a point on it by the technique), each of solid-angle pdf p_i = tree pmf x
// technique pdf -- a point or spot light the tree chose is an atom of the same measure, of "pdf" its pmf (a soft one:
// pmf x its cone's pdf) -- and weighed w_i = p_hat(x_i) / p_i; one, y, is kept with probability w_y / sum w (weighted
// reservoir sampling) and only its shadow ray is traced, with f(y) W, W = (sum w / M) / p_hat(y).
//
// The target p_hat(x) is the luminance of what the light sample x would add unoccluded: BSDF x radiance x cosine (x
// the world medium's transmittance), times its MIS weight against the BSDF sample.  So w_i is the luminance of the
// candidate's ordinary estimate f / p_i, which the candidate queues on the shadow queue as every light sample does:
// the reservoir is that queue's tail, and f(y) W is y's entry times (sum w / M) / w_y.
//
// Unbiased: for each candidate E[f(x_i) / p_i] is the light strategy's integral, and the resampling keeps that mean
// wherever p_hat > 0 where the integrand f w_MIS > 0 (it does: the unoccluded value bounds the occluded one).  MIS with
// the BSDF sample: y's density is not p_i, but both strategies weigh a direction with the proposal's pdf p_i
// (LightSamplingAt::PDF: the BSDF ray that finds a light weighs it against p_i too), so the two weights still sum to 1
// for every direction -- a partition of the integrand, which each strategy estimates without bias; the weights are
// no longer the heuristic of the densities actually drawn, which costs optimality only (docs/light_selection_ris.md).
#pragma once

#include <cmath>
#include <vector>

#include "core/rng.h"
#include "render/sampling_util.h"
#include "shadow_queue.h"

namespace sphrect::render {

// Candidate k > 0's pattern point: the light sample's, shifted by a random offset modulo 1 (Cranley-Patterson), so
// that each candidate is uniform and keeps the pattern's stratification over the pixel's samples (the kept one,
// picked among them by a random number, does not: docs/light_selection_ris.md, "Few lights").  The candidates need
// not be independent: the estimator is unbiased given each one's marginal density.
static inline Point2<float> ShiftedCandidatePoint(Point2<float> p, PCG32& rng) {
    auto shift = [&](float x) {
        const float y = x + rng.NextFloat();
        return std::fmin(y < 1 ? y : y - 1, kOneMinusEpsilonF);
    };
    const float u = shift(p.u);
    return {u, shift(p.v)};
}

// The reservoir of one resampled light sample, kept on the shadow queue of `sink` after the entries queued before it.
// Each candidate queues its estimate f / p_i (at most one entry) on CandidateSink(), then Weigh keeps or drops it;
// Finish gives the kept one its weight.  No allocation but the queue's own growth.
class LightSampleReservoir {
  public:
    explicit LightSampleReservoir(const ShadowSink& sink) : sink_(sink), slot_(sink.queue->size()) {}

    // Where candidates are queued: unscaled, so that the weights depend on the light sample alone.
    ShadowSink CandidateSink() const { return {sink_.queue, sink_.sample}; }

    // After a candidate was queued (or nothing, where it adds nothing: w 0): keeps it with probability w / sum w
    // (u uniform in [0, 1)), its entry moved to the reservoir's slot; otherwise removed.
    void Weigh(float u) {
        ++candidates_;
        std::vector<DeferredShadowRay>& queue = *sink_.queue;
        if (queue.size() == slot_ + (kept_ ? 1 : 0)) return;
        const float w = Luminance(queue.back().contribution);
        if (w > 0 && std::isfinite(w)) {
            weight_sum_ += w;
            if (u * weight_sum_ < w) {
                if (kept_) queue[slot_] = queue.back();
                kept_ = true;
                kept_weight_ = w;
                if (queue.size() == slot_ + 1) return;  // the first kept: already in its slot
            }
        }
        queue.pop_back();
    }

    // The kept candidate's entry becomes f(y) W = (f(y) / p_y) (sum w / M) / w_y, times the sink's scale.
    void Finish() const {
        if (!kept_) return;
        DeferredShadowRay& entry = (*sink_.queue)[slot_];
        entry.contribution = entry.contribution * sink_.scale * float(weight_sum_ / candidates_ / kept_weight_);
    }

  private:
    const ShadowSink& sink_;
    size_t slot_;  // the kept candidate's entry, when kept_
    bool kept_ = false;
    int candidates_ = 0;
    double weight_sum_ = 0;
    double kept_weight_ = 0;
};

}  // namespace sphrect::render
