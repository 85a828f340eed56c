#pragma once
// Progress reporting for long operations. The callback returns false to cancel; the
// operation then throws ggg::Cancelled at its next check point.
#include <functional>
#include <string_view>

#include "ggg/error.hpp"

namespace ggg {

using ProgressCallback = std::function<bool(double fraction, std::string_view message)>;

inline void report(const ProgressCallback& progress, double fraction, std::string_view message) {
    if (progress && !progress(fraction, message)) {
        throw Cancelled{};
    }
}

} // namespace ggg
