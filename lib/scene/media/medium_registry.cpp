#include "scene/media/medium_registry.h"

#include <string>

#include "scene/media/grid_medium.h"
#include "scene/media/homogeneous_medium.h"

namespace vpm {

const std::vector<MediumType>& medium_types() {
    static const std::vector<MediumType> types = {
        {"homogeneous", make_homogeneous_medium, false},
        {"grid", make_grid_medium, true},
    };
    return types;
}

std::unique_ptr<Medium> make_medium(Params& p, const MediumType** type_out) {
    std::vector<std::string> names;
    for (const MediumType& t : medium_types()) names.push_back(t.name);
    const std::string type = p.choice("type", names);
    std::unique_ptr<Medium> medium;
    for (const MediumType& t : medium_types())
        if (type == t.name) {
            medium = t.create(p);
            if (type_out) *type_out = &t;
        }
    p.finish();
    return medium;
}

}  // namespace vpm
