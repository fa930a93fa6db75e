#include "photon/walk_group_split.h"

#include "core/error.h"

namespace vpm {

std::vector<PhotonMap> split_by_walk_group(const PhotonMap& map, int parts) {
    if (parts < 1 || kWalkGroups % parts != 0)
        throw Error("split_by_walk_group: parts = " + std::to_string(parts) + " must divide the " +
                    std::to_string(kWalkGroups) + " walk groups");
    std::vector<std::vector<PhotonInput>> inputs(static_cast<size_t>(parts));
    for (auto& v : inputs) v.reserve(map.size() / size_t(parts) + 1);
    for (size_t i = 0; i < map.size(); ++i) {
        PhotonInput p;
        p.position = map.position(i);
        p.direction = map.direction(i);
        p.power = map.power(i) * double(parts);
        p.group = walk_group(map.record(i).reserved);
        inputs[size_t(p.group % parts)].push_back(p);
    }
    std::vector<PhotonMap> out;
    out.reserve(size_t(parts));
    for (auto& v : inputs) out.emplace_back(v);
    return out;
}

}  // namespace vpm
