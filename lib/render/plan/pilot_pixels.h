#pragma once
// Where the auto pilot's pixels go (render/plan/map_noise_pilot.h). A pixel whose rays meet no surface
// and no medium (optical depth 0) shows the background: its radiance is fixed and it adds nothing to
// V_camera, V_map or the bias. The pilot's figures are averages over the image's pixels, so its
// pixels are spread over the pixels that can vary instead, and each figure is that average times
// their share of the image (a stratified estimate: the other stratum is exactly 0). The pixels that
// can vary are found from the centres of a kPilotCandidateSide^2 grid of image blocks (one ray each).
// Where a small object leaves most of the image empty the 8 x 8 block centres put a few pixels on
// it: in smoke beside a sphere light (docs/studies/emission_guides.md section 26, h6) about 6 of 64, and the pilot read
// the map's variance 7x low. Where every candidate sees something the pixels are the block centres
// as before. Deterministic and scale-invariant (geometry and optical depths only).
#include <functional>
#include <utility>
#include <vector>

namespace vpm {

constexpr int kPilotCandidateSide = 32;

struct PilotPixels {
    std::vector<std::pair<int, int>> pixels;   // the pilot's pixels (x, y)
    std::vector<std::pair<int, int>> spread;   // V_camera's second grid (render/plan/map_noise_pilot.h)
    std::vector<std::pair<int, int>> background;   // up to side^2 candidates that see nothing (their cost)
    double seen_fraction = 1.0;                // share of the candidates that see something
};

// `side` x `side` pilot pixels and `spread_side` x `spread_side` spread pixels over a width x height
// image; sees(x, y): whether pixel (x, y)'s centre ray meets a surface or a medium.
PilotPixels choose_pilot_pixels(int width, int height, int side, int spread_side, const std::function<bool(int, int)>& sees);

// The pixel at the centre of block j of a side x side grid over a width x height image.
std::pair<int, int> block_centre(int j, int side, int width, int height);

}  // namespace vpm
