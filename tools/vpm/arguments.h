#pragma once
// Command-line parsing for every subcommand, so they all fail the same way: a bad command line
// becomes a UsageError, which main prints as one line "vpm <cmd>: error: <what> (see vpm <cmd>
// --help)" and turns into exit code 2 (kExitUsage). --help prints the help to stdout.
#include <cmath>
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>

#include "core/error.h"

namespace vpm::cli {

// Exit codes of `vpm` (README.md and docs/rendering.md, "Errors and exit codes").
constexpr int kExitOk = 0;
constexpr int kExitError = 1;      // bad input, missing/corrupt file, unwritable output; stress: a cell failed
constexpr int kExitUsage = 2;      // bad command line (unknown option, bad value, missing argument)
constexpr int kExitInternal = 3;   // a bug: an unexpected exception

class UsageError : public vpm::Error {
public:
    using vpm::Error::Error;
};

// A finite number in [lo, hi] (hi may be infinite: "at least lo"). CLI::Range lets NaN through
// (every comparison with it is false) and prints its bounds in full (1e300 as 301 digits).
inline CLI::Validator finite_in(double lo, double hi, const std::string& shown) {
    return CLI::Validator(
        [lo, hi, shown](std::string& text) -> std::string {
            double v = 0.0;
            size_t used = 0;
            try {
                v = std::stod(text, &used);
            } catch (const std::exception&) {
                return "'" + text + "' is not a number (allowed: " + shown + ")";
            }
            if (used != text.size() || !std::isfinite(v) || v < lo || v > hi)
                return "'" + text + "' is out of range (allowed: " + shown + ")";
            return std::string();
        },
        shown);
}

// Parses argv into `app`. Returns false when --help was answered (the command returns 0);
// throws UsageError for anything CLI11 rejects.
inline bool parse_arguments(CLI::App& app, int argc, char** argv) {
    try {
        app.parse(argc, argv);
        return true;
    } catch (const CLI::CallForHelp&) {
        std::cout << app.help();
        return false;
    } catch (const CLI::CallForAllHelp&) {
        std::cout << app.help("", CLI::AppFormatMode::All);
        return false;
    } catch (const CLI::ParseError& e) {
        std::string what = e.what();
        while (!what.empty() && (what.back() == '\n' || what.back() == ' ')) what.pop_back();
        throw UsageError(what + " (see " + app.get_name() + " --help)");
    }
}

}  // namespace vpm::cli
