// A fast search for the first value outside a range, shared by the library's depth checks
// and the EXR reader's (both scan every sample of a map before any work).
#pragma once

#include <algorithm>
#include <cstddef>

namespace msmcl::detail {

/// Index of the first value that is NaN or outside [low, high] (finite bounds, so an
/// infinity is outside too), or `count` when there is none. Blocks are checked without a
/// branch per value, which lets the compiler vectorize the scan; only a block that holds
/// a bad value is searched value by value.
inline std::size_t first_outside(const float* values, std::size_t count, float low, float high) {
    constexpr std::size_t block = 1024;
    for (std::size_t start = 0; start < count; start += block) {
        const std::size_t end = std::min(count, start + block);
        bool inside = true;
        for (std::size_t i = start; i < end; ++i) inside &= (values[i] >= low) & (values[i] <= high);
        if (inside) continue;
        for (std::size_t i = start; i < end; ++i)
            if (!(values[i] >= low && values[i] <= high)) return i;
    }
    return count;
}

} // namespace msmcl::detail
