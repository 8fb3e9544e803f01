// A cheap timestamp for the time spent in light sampling, read around every light-sampling
// call (TimedLightSamplingAt): the TSC on x86, converted to seconds with a rate measured per
// pass (Renderer::RenderPass); elsewhere nanoseconds of the steady clock.
#pragma once

#include <chrono>
#include <cstdint>

#if defined(__x86_64__) || defined(__i386__)
#include <x86intrin.h>
#endif

namespace sphrect::render {

inline uint64_t ReadTicks() {
#if defined(__x86_64__) || defined(__i386__)
    return __rdtsc();
#else
    return uint64_t(
        std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
            .count());
#endif
}

// ReadTicks() units per second, measured once (over ~2 ms of the steady clock) at the first call.
double TicksPerSecond();

// `seconds` in ReadTicks() units; 0 without measuring the rate (the measurement spins ~2 ms, once per process: only
// what needs ticks pays it).
inline uint64_t SecondsToTicks(double seconds) { return seconds > 0 ? uint64_t(seconds * TicksPerSecond()) : 0; }

// Busy-waits `ticks` ReadTicks() units (RenderOptions::added_shading_cost).
inline void SpinTicks(uint64_t ticks) {
    const uint64_t end = ReadTicks() + ticks;
    while (ReadTicks() < end) {
    }
}

}  // namespace sphrect::render
