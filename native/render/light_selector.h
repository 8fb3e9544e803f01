// Choosing one of several emitters by power.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/rng.h"  // kOneMinusEpsilonF

namespace sphrect::render {

// Picks an index with probability proportional to its power (area lights: AreaLightPower).
// Entries with zero power are never picked.
struct LightSelector {
    std::vector<float> cdf;  // cdf[i] = P(index <= i)
    std::vector<float> pmf;

    void Build(const std::vector<double>& powers) {
        pmf.assign(powers.size(), 0.0f);
        cdf.assign(powers.size(), 0.0f);
        double total = 0;
        std::vector<double> power(powers.size());
        for (size_t i = 0; i < powers.size(); ++i) {
            power[i] = std::isfinite(powers[i]) && powers[i] > 0 ? powers[i] : 0.0;
            total += power[i];
        }
        double acc = 0;
        for (size_t i = 0; i < powers.size(); ++i) {
            pmf[i] = total > 0 ? float(power[i] / total) : 0.0f;
            acc += power[i];
            cdf[i] = total > 0 ? float(acc / total) : 0.0f;
        }
        if (!cdf.empty() && total > 0) cdf.back() = 1.0f;
    }
    bool Empty() const { return cdf.empty() || cdf.back() <= 0; }
    // Index of the light for uniform u in [0,1); never a light with zero probability.
    int Select(float u) const {
        int i = int(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin());
        i = std::min(i, int(cdf.size()) - 1);
        while (i > 0 && pmf[i] == 0) --i;
        return i;
    }
    // The same choice from u, and u rescaled to [0,1) within the chosen index's interval
    // [cdf[i-1], cdf[i]): (u - cdf[i-1]) / (cdf[i] - cdf[i-1]), clamped below 1 (pbrt-v4's
    // SampleDiscrete).  Given the choice, the rescaled u is uniform again, so one stratified
    // coordinate both picks the index and places the sample: each index gets its share of a
    // stratified set of u exactly (up to one stratum), not only on average.  With one entry
    // the interval is [0, 1) and u comes back unchanged (u / 1 is exact).  The rescale costs
    // log2(1 / width) of u's 24 bits (2 bits for 4 equal lights).
    int SelectRemapped(float u, float* u_remapped) const {
        const int i = Select(u);
        const float lo = i > 0 ? cdf[i - 1] : 0.0f, width = cdf[i] - lo;
        const float r = width > 0 ? (u - lo) / width : 0.0f;
        *u_remapped = std::clamp(r, 0.0f, kOneMinusEpsilonF);
        return i;
    }
};

}  // namespace sphrect::render
