// Temporary stand-alone entry point so that `vpm study` runs before the lead's main() and
// subcommand registry exist. main is a WEAK symbol: a regular main() elsewhere in tools/vpm
// overrides it at link time without conflict. Delete this file once the registry dispatches
// "study" to run_study().
#include <cstdio>
#include <cstring>

#include "cmd_study.h"

__attribute__((weak)) int main(int argc, char** argv) {
    if (argc >= 2 && std::strcmp(argv[1], "study") == 0) return vpm::run_study(argc - 1, argv + 1);
    std::fprintf(stderr, "usage: vpm study [--help] ...   (only 'study' is available in this build)\n");
    return 2;
}
