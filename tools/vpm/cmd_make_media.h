#pragma once
// `vpm make-media`: writes the small procedural VDB files shipped in media/.
namespace vpm {
int run_make_media(int argc, char** argv);
}  // namespace vpm
