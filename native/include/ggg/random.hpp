#pragma once
// The library's random numbers: splitmix64, small and fast, and the same sequence on every
// platform (the standard distributions are not, which would break "same seed, same
// result"). Each user seeds its own stream per unit of work (a component, a block), so
// that results do not depend on thread scheduling.
#include <cstdint>

namespace ggg {

struct Random {
    std::uint64_t state;

    std::uint64_t next() {
        std::uint64_t z = (state += 0x9E3779B97F4A7C15ULL);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
        return z ^ (z >> 31);
    }
    // Uniform in [0, n) by multiply-shift (n < 2^32).
    std::uint32_t below(std::uint32_t n) { return static_cast<std::uint32_t>(((next() >> 32) * n) >> 32); }
    // Uniform in [low, high), from the top 53 bits.
    double uniform(double low, double high) { return low + (high - low) * static_cast<double>(next() >> 11) * 0x1.0p-53; }
};

} // namespace ggg
