// vpm stress [--out DIR] [--quick] [--md FILE] [--only TEXT]: the stress matrix of issue 6.
#include <algorithm>
#include <fstream>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <thread>

#include <CLI/CLI.hpp>
#include <unistd.h>

#include "analysis/matrix/stress.h"
#include "arguments.h"
#include "command.h"
#include "data_files.h"
#include "core/error.h"
#include "core/progress.h"
#include "render/run/image_io.h"
#include "render/run/staged_file.h"

namespace {

int run_stress_command(int argc, char** argv) {
    CLI::App app(
        "Run the stress matrix (stiff and extreme cases, configs/stress/) and write it as a Markdown table.\n"
        "Every cell reports NaN/Inf counts, the photon pass's energy balance, truncated photon paths, time and\n"
        "the relative error against a reference. Exit code 1 when any cell has a NaN/Inf or an energy\n"
        "imbalance above 1e-6.",
        "vpm stress");
    std::string out = "out/stress", md, configs = vpm::cli::data_file("configs/stress").string(), only;
    bool quick = false;
    app.add_option("--out", out, "Scratch folder (the dense-voxel VDB goes here)")->capture_default_str();
    app.add_option("--md", md, "Markdown table to write (default: OUT/STRESS.md)");
    app.add_option("--configs", configs, "Folder with the base scenes")->capture_default_str()->check(CLI::ExistingDirectory);
    app.add_option("--only", only, "Run only cells whose 'axis/value' contains TEXT");
    app.add_flag("--quick", quick, "CI-sized subset: 8x8 images, 2000 photons, no photon counts above 1e3, no path-traced references");
    if (!vpm::cli::parse_arguments(app, argc, argv)) return 0;
    if (!only.empty()) {   // a filter that picks nothing would run 0 cells and report "all ok"
        const std::vector<std::string> keys = vpm::stress_cell_keys(quick);
        if (std::none_of(keys.begin(), keys.end(), [&](const std::string& k) { return k.find(only) != std::string::npos; }))
            throw vpm::cli::UsageError("--only '" + only + "' matches none of the " + std::to_string(keys.size()) +
                                       (quick ? " --quick" : "") + " cells (names are 'axis/value', e.g. '" + keys.front() + "')");
    }
    if (md.empty()) md = out + "/STRESS.md";
    // Before the work: the scratch folder and the table must be writable.
    vpm::prepare_output_folder(out);
    vpm::check_output_file(md);

    vpm::StressOptions o;
    o.quick = quick;
    o.configs = configs;
    o.out = out;
    o.log = &std::cerr;
    if (!only.empty()) o.filter = [only](const std::string& key) { return key.find(only) != std::string::npos; };
    const vpm::StressReport report = vpm::run_stress(o);

    char host[256] = "unknown";
    gethostname(host, sizeof host - 1);
    std::ostringstream machine;
    machine << host << ", " << std::thread::hardware_concurrency() << " threads, "
            << vpm::physical_memory_bytes() / (1u << 30) << " GiB";
    std::string command = "vpm stress";
    for (int i = 1; i < argc; ++i) command += std::string(" ") + argv[i];
    const std::string text = report.to_markdown(command, machine.str());
    vpm::write_text_atomic(md, text);
    std::cerr << "wrote " << md << " (" << report.cells.size() << " cells, " << report.seconds << " s): "
              << (report.all_ok() ? "all ok" : "FAILURES") << "\n";
    return report.all_ok() ? 0 : 1;
}

}  // namespace

VPM_REGISTER_COMMAND({"stress", "run the stress matrix (extreme cases) and write STRESS.md", run_stress_command});
