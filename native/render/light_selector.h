// Choosing one of several emitters by power.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

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
};

}  // namespace sphrect::render
