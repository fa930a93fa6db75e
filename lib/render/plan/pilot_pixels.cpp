#include "render/plan/pilot_pixels.h"

#include <algorithm>

namespace vpm {

std::pair<int, int> block_centre(int j, int side, int width, int height) {
    return {std::min(width - 1, int((j % side + 0.5) / side * width)), std::min(height - 1, int((j / side + 0.5) / side * height))};
}

namespace {

// The block centres of a side x side grid, or `count` pixels spread evenly (in scan order) over `seen`.
std::vector<std::pair<int, int>> spread_over(const std::vector<std::pair<int, int>>& seen, bool all_seen, int side,
                                             int width, int height) {
    const int count = side * side;
    std::vector<std::pair<int, int>> out(static_cast<size_t>(count));
    for (int i = 0; i < count; ++i)
        out[size_t(i)] = all_seen ? block_centre(i, side, width, height)
                                  : seen[size_t((i + 0.5) * double(seen.size()) / double(count))];
    return out;
}

}  // namespace

PilotPixels choose_pilot_pixels(int width, int height, int side, int spread_side, const std::function<bool(int, int)>& sees) {
    constexpr int kCandidates = kPilotCandidateSide * kPilotCandidateSide;
    std::vector<std::pair<int, int>> seen, unseen;
    for (int j = 0; j < kCandidates; ++j) {
        const auto p = block_centre(j, kPilotCandidateSide, width, height);
        (sees(p.first, p.second) ? seen : unseen).push_back(p);
    }
    // Nothing seen: nothing varies, any pixels do (and every figure is 0 anyway).
    const bool all_seen = seen.size() == size_t(kCandidates) || seen.empty();
    PilotPixels out;
    out.seen_fraction = all_seen ? 1.0 : double(seen.size()) / double(kCandidates);
    out.pixels = spread_over(seen, all_seen, side, width, height);
    out.spread = spread_over(seen, all_seen, spread_side, width, height);
    if (!all_seen) {
        const size_t n = std::min(unseen.size(), size_t(side * side));
        for (size_t i = 0; i < n; ++i) out.background.push_back(unseen[size_t((i + 0.5) * double(unseen.size()) / double(n))]);
    }
    return out;
}

}  // namespace vpm
