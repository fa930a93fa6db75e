// vpm: volumetric photon mapping research renderer. Dispatches to the registered subcommands.
#include <algorithm>
#include <cstring>
#include <iostream>

#include "arguments.h"
#include "command.h"
#include "core/build_info.h"
#include "core/error.h"
#include "render/run/staged_file.h"

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
           "usage: vpm COMMAND [options]    (vpm COMMAND --help for its options)\n"
           "       vpm --version\n\ncommands:\n";
    for (const auto& c : vpm::cli::commands()) {
        out << "  " << c.name;
        for (size_t i = c.name.size(); i < 12; ++i) out << ' ';
        out << c.summary << "\n";
    }
    out << "\nexit codes: 0 success; 1 error (bad input, missing or corrupt file, unwritable output;\n"
           "vpm stress: a cell failed); 2 bad command line; 3 internal error; killed by a signal:\n"
           "the shell's 128 + signal number (interrupted outputs leave no temporary files)\n";
}

int main(int argc, char** argv) {
    using namespace vpm::cli;
    vpm::remove_temporaries_on_signals();
    if (argc >= 2 && (!std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h") || !std::strcmp(argv[1], "help"))) {
        print_usage(std::cout);
        return kExitOk;
    }
    if (argc >= 2 && (!std::strcmp(argv[1], "--version") || !std::strcmp(argv[1], "-V"))) {
        std::cout << "vpm " << vpm::vpm_version() << " (git " << vpm::git_revision() << ")\n";
        return kExitOk;
    }
    if (argc < 2) {
        std::cerr << "vpm: error: no command given (see vpm --help)\n";
        return kExitUsage;
    }
    for (const auto& c : vpm::cli::commands()) {
        if (c.name != argv[1]) continue;
        std::string program = std::string("vpm ") + argv[1];
        std::vector<char*> args(argv + 1, argv + argc);
        args[0] = program.data();
        try {
            return c.run(int(args.size()), args.data());
        } catch (const UsageError& e) {
            const std::string what = e.what();
            std::cerr << "vpm " << c.name << ": error: " << what
                      << (what.find("--help") == std::string::npos ? " (see vpm " + c.name + " --help)" : "") << "\n";
            return kExitUsage;
        } catch (const vpm::Error& e) {
            std::cerr << "vpm " << c.name << ": error: " << e.what() << "\n";
            return kExitError;
        } catch (const std::exception& e) {
            std::cerr << "vpm " << c.name << ": internal error: " << e.what() << "\n";
            return kExitInternal;
        }
    }
    std::string names;
    for (const auto& c : vpm::cli::commands()) names += (names.empty() ? "" : ", ") + c.name;
    std::cerr << "vpm: error: unknown command '" << argv[1] << "' (commands: " << names << "; see vpm --help)\n";
    return kExitUsage;
}
