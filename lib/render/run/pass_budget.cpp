#include "render/run/pass_budget.h"

#include <algorithm>
#include <cmath>

namespace vpm {

PassBudget::PassBudget(const RenderSettings& settings, const Integrator& integrator, const RenderStats& render)
    : settings_(settings), integrator_(integrator), render_(render),
      clock_stops_(settings.time_limit > 0 && settings.time_limit_passes == 0),
      fixed_passes_(settings.time_limit_passes > 0 ? settings.time_limit_passes : settings.passes) {}

int64_t PassBudget::next_group(int64_t group) const {
    if (done_ < fixed_passes_) return std::min<int64_t>(group, fixed_passes_ - done_);
    const double per_pass = seconds_per_pass();
    const double fit = per_pass > 0.0 ? std::floor((settings_.time_limit - timer_.seconds()) / per_pass) : double(group);
    const int64_t n = std::max<int64_t>(1, std::min<int64_t>(group, int64_t(std::min(fit, double(group)))));
    return std::min<int64_t>(n, kMaxRunPasses - settings_.first_pass - done_);
}

void PassBudget::finished(int64_t n) {
    const bool first = done_ == 0;
    done_ += n;
    if (first) {
        first_group_seconds_ = timer_.seconds();
        first_group_passes_ = done_;
    }
}

bool PassBudget::more() const {
    if (done_ < fixed_passes_) return true;
    return clock_stops_ && timer_.seconds() + seconds_per_pass() <= settings_.time_limit &&
           done_ < kMaxRunPasses - settings_.first_pass;
}

double PassBudget::seconds_per_pass() const {
    if (done_ > first_group_passes_) return (timer_.seconds() - first_group_seconds_) / double(done_ - first_group_passes_);
    return (integrator_.stateless_passes() ? render_.seconds : timer_.seconds() - integrator_.one_off_seconds()) /
           double(done_);
}

}  // namespace vpm
