#pragma once
// Subcommands of the `vpm` executable. Each lives in its own cmd_*.cpp and registers itself
// with a static VPM_REGISTER_COMMAND, so adding a subcommand touches no other file.
#include <functional>
#include <string>
#include <vector>

namespace vpm::cli {

struct Command {
    std::string name;
    std::string summary;
    std::function<int(int argc, char** argv)> run;   // argv[0] is "vpm NAME"
};

bool register_command(Command command);
const std::vector<Command>& commands();

}  // namespace vpm::cli

#define VPM_CONCAT_INNER(a, b) a##b
#define VPM_CONCAT(a, b) VPM_CONCAT_INNER(a, b)
#define VPM_REGISTER_COMMAND(...) \
    static const bool VPM_CONCAT(vpm_command_registered_, __LINE__) = ::vpm::cli::register_command(__VA_ARGS__)
