// vpm: volumetric photon mapping research renderer. Dispatches to the registered subcommands.
#include <algorithm>
#include <cstring>
#include <iostream>

#include "command.h"
#include "core/error.h"

namespace vpm::cli {

namespace {
std::vector<Command>& registry() {
    static std::vector<Command> list;
    return list;
}
}  // namespace

bool register_command(Command command) {
    registry().push_back(std::move(command));
    std::sort(registry().begin(), registry().end(), [](const Command& a, const Command& b) { return a.name < b.name; });
    return true;
}

const std::vector<Command>& commands() { return registry(); }

}  // namespace vpm::cli

static void print_usage(std::ostream& out) {
    out << "vpm: volumetric photon mapping in participating media\n\n"
           "usage: vpm COMMAND [options]    (vpm COMMAND --help for its options)\n\ncommands:\n";
    for (const auto& c : vpm::cli::commands()) {
        out << "  " << c.name;
        for (size_t i = c.name.size(); i < 12; ++i) out << ' ';
        out << c.summary << "\n";
    }
}

int main(int argc, char** argv) {
    if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h") || !std::strcmp(argv[1], "help")) {
        print_usage(std::cout);
        return argc < 2 ? 2 : 0;
    }
    for (const auto& c : vpm::cli::commands()) {
        if (c.name != argv[1]) continue;
        std::string program = std::string("vpm ") + argv[1];
        std::vector<char*> args(argv + 1, argv + argc);
        args[0] = program.data();
        try {
            return c.run(int(args.size()), args.data());
        } catch (const vpm::Error& e) {
            std::cerr << "vpm " << c.name << ": error: " << e.what() << "\n";
            return 1;
        } catch (const std::exception& e) {
            std::cerr << "vpm " << c.name << ": internal error: " << e.what() << "\n";
            return 3;
        }
    }
    std::cerr << "vpm: unknown command '" << argv[1] << "'\n\n";
    print_usage(std::cerr);
    return 2;
}
