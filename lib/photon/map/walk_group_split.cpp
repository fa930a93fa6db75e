#include "photon/map/walk_group_split.h"

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
        p.walk = map.walk(i);   // whole walks go to one part: its walk neighbourhoods stay walks
        const uint8_t g = walk_group(map.record(i).reserved);
        // Within its part a photon's group becomes g / parts, so that every part still holds both
        // parities (photons.clustering = "leave_group_out" splits by parity: with g kept, a part of
        // one parity left its other half empty and every query gathered the whole map, 300 s of
        // pilot in the thin cube).
        p.group = uint8_t(g / parts);
        inputs[size_t(g % parts)].push_back(p);
    }
    std::vector<PhotonMap> out;
    out.reserve(size_t(parts));
    for (auto& v : inputs) out.emplace_back(v);
    return out;
}

}  // namespace vpm
