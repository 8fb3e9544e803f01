// Multiple importance sampling of one sample from each of two strategies (Veach 1997, ch. 9):
// the heuristics the renderer offers, their names and the weight each gives.
#pragma once

#include <array>
#include <cmath>

namespace sphrect::render {

enum class MisMode { None, Balance, Power };

constexpr std::array<MisMode, 3> kAllMisModes = {MisMode::None, MisMode::Balance, MisMode::Power};

constexpr const char* MisModeName(MisMode m) {
    switch (m) {
        case MisMode::None: return "none";
        case MisMode::Balance: return "balance";
        case MisMode::Power: return "power";
    }
    return "?";
}

// Weight of a sample drawn by the strategy with density pdf_this, the other having pdf_other:
// balance p / (p + q), power p^2 / (p^2 + q^2); None: 1 (no combination).  Always inlined, as ShadowSink::Add and
// OffsetOrigin: the link-time optimiser otherwise moves these small hot calls out of the shading loops as the kernel
// grows (docs/architecture.md, measured choices).
[[gnu::always_inline]] inline float MisWeight(MisMode m, float pdf_this, float pdf_other) {
    switch (m) {
        case MisMode::None: return 1.0f;
        case MisMode::Balance: return pdf_this / (pdf_this + pdf_other);
        case MisMode::Power: {
            const float a = pdf_this * pdf_this, b = pdf_other * pdf_other;
            // Squares of huge pdfs overflow to inf (inf/inf = NaN): fall back to the ratio form.
            if (!std::isfinite(a + b)) return pdf_this >= pdf_other ? 1.0f : 0.0f;
            return a / (a + b);
        }
    }
    return 1.0f;
}

}  // namespace sphrect::render
