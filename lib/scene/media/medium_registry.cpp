#include "scene/media/medium_registry.h"

#include "core/registry.h"

namespace vpm {

// Each type's factory, defined in its own file.
std::unique_ptr<Medium> make_homogeneous_medium(Params&);
std::unique_ptr<Medium> make_grid_medium(Params&);

const std::vector<MediumType>& medium_types() {
    static const std::vector<MediumType> types = {
        {"homogeneous", make_homogeneous_medium, false},
        {"grid", make_grid_medium, true},
    };
    return types;
}

std::vector<std::string> medium_names() { return registry_names(medium_types()); }

std::unique_ptr<Medium> make_medium(Params& p, const MediumType** type_out) {
    const MediumType* type = registry_find(medium_types(), p.choice("type", medium_names()));
    std::unique_ptr<Medium> medium = type->create(p);
    if (type_out) *type_out = type;
    p.finish();
    return medium;
}

}  // namespace vpm
