// Standard Direct3D 11 multisample positions (D3D11_STANDARD_MULTISAMPLE_PATTERN), in
// 1/16 pixel units relative to the pixel centre, y pointing down.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace msmcl::data {

struct SampleOffset {
    int x16;
    int y16;
};

/// Positions for 1, 2, 4, 8 or 16 samples per pixel (1 = the pixel centre).
inline std::vector<SampleOffset> standard_sample_pattern(int samples) {
    switch (samples) {
    case 1: return {{0, 0}};
    case 2: return {{4, 4}, {-4, -4}};
    case 4: return {{-2, -6}, {6, -2}, {-6, 2}, {2, 6}};
    case 8: return {{1, -3}, {-1, 3}, {5, 1}, {-3, -5}, {-5, 5}, {-7, -1}, {3, 7}, {7, -7}};
    case 16:
        return {{1, 1},   {-1, -3}, {-3, 2}, {4, -1}, {-5, -2}, {2, 5},  {5, 3},   {3, -5},
                {-2, 6}, {0, -7},  {-4, -6}, {-6, 4}, {-8, 0},  {7, -4}, {6, 7},   {-7, -8}};
    default: throw std::invalid_argument("no standard pattern for " + std::to_string(samples) + " samples");
    }
}

} // namespace msmcl::data
