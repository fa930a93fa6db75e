#include "transport/walk_settings.h"

#include "config/params.h"

namespace vpm {

WalkSettings WalkSettings::read(Params& render) {
    WalkSettings w;
    w.max_depth = int(render.integer("max_depth", w.max_depth, Range::closed(-1, 1 << 20)));
    w.rr_depth = int(render.integer("rr_depth", w.rr_depth, Range::closed(1, 1 << 20)));
    w.mis = render.boolean("mis", w.mis);
    w.equiangular = render.boolean("equiangular", w.equiangular);
    return w;
}

}  // namespace vpm
