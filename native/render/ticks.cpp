#include "ticks.h"

#include <chrono>

namespace sphrect::render {

double TicksPerSecond() {
    static const double rate = [] {
        using Clock = std::chrono::steady_clock;
        const auto t0 = Clock::now();
        const uint64_t k0 = ReadTicks();
        while (Clock::now() - t0 < std::chrono::milliseconds(2)) {
        }
        const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
        return double(ReadTicks() - k0) / seconds;
    }();
    return rate;
}

}  // namespace sphrect::render
