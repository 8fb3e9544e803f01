// The batched kernels' tests run once per instruction set the build has code for and this machine runs (AVX-512,
// AVX2, SSE4, ...), each forced in turn (Highway's SetSupportedTargetsForTest).
#pragma once

#include <gtest/gtest.h>

#include <cstdint>

#include "hwy/targets.h"

namespace sphrect {

// Runs `check` once per instruction set the batch can take here, that one forced.
template <class F>
void ForEachTarget(F&& check) {
    for (const int64_t target : hwy::SupportedAndGeneratedTargets()) {
        hwy::SetSupportedTargetsForTest(target);
        SCOPED_TRACE(hwy::TargetName(target));
        check();
    }
    hwy::SetSupportedTargetsForTest(0);  // back to what the machine supports
}

}  // namespace sphrect
