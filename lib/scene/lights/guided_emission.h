#pragma once
// A light's photons drawn in part from a DirectionGuide (scene/emission_guides.h): a one-sample
// mixture of its own emission, with probability 1 - share, and the guide, with probability share.
// Each photon is weighted by the mixture's density, so the expected power in every direction is
// the light's own. Inactive (no guide): the light's own emission only, with its own random numbers.
#include <memory>

#include "core/sampling/rng.h"
#include "scene/lights/direction_guide.h"

namespace vpm {

class GuidedEmission {
public:
    // An empty guide (or none) makes the mixture inactive.
    void set(std::shared_ptr<const DirectionGuide> guide, double share) {
        guide_ = guide && !guide->empty() ? std::move(guide) : nullptr;
        share_ = share;
    }
    bool active() const { return guide_ != nullptr; }
    double share() const { return share_; }
    const DirectionGuide& guide() const { return *guide_; }

    // A direction of the mixture: one number picks the strategy, then two go to the guide or
    // own(rng) draws the light's own direction.
    template <class OwnDirection>
    Vec3 sample(Rng& rng, const OwnDirection& own) const {
        if (rng.uniform() < share_) {
            const double u1 = rng.uniform(), u2 = rng.uniform();
            return guide_->sample(u1, u2);
        }
        return own(rng);
    }
    // The mixture's solid-angle density at w, given the light's own density there.
    double pdf(double own_pdf, const Vec3& w) const { return (1.0 - share_) * own_pdf + share_ * guide_->pdf(w); }

private:
    std::shared_ptr<const DirectionGuide> guide_;
    double share_ = 0.0;
};

}  // namespace vpm
