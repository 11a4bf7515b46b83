// SPDX-License-Identifier: MIT
#include "vsculpt/app/Cli.h"

#include "vsculpt/app/Summary.h"
#include "vsculpt/core/Config.h"
#include "vsculpt/core/Sculpture.h"

#include <CLI/CLI.hpp>

#include <exception>
#include <filesystem>
#include <ostream>

namespace vsculpt::app {

int runCli(int argc, const char* const* argv, std::ostream& out, std::ostream& err) {
    CLI::App cli{
        "vsculpt - immersive virtual-sculpting modeler.\n"
        "Without a subcommand it builds the initial sculpture from the config and prints a\n"
        "summary (tool levels, calibration, initial shape). The sculpting window, playback\n"
        "scripts and device input are not built yet: see README.md, 'What works'."};
    cli.set_version_flag("--version", "vsculpt 0.1.0");
    std::string configPath = core::defaultConfigPath().string();
    cli.add_option("--config", configPath, "Config file (JSON with comments; docs/config.md)")
        ->capture_default_str();

    try {
        cli.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // CLI11 prints help/version to out and usage errors to err with its own exit codes.
        return cli.exit(e, out, err) == 0 ? 0 : 2;
    }

    try {
        const core::SculptConfig cfg = core::loadConfig(configPath);
        const core::Sculpture sculpture(cfg);
        printSummary(sculpture, out);
        return 0;
    } catch (const core::ConfigError& e) {
        err << "vsculpt: error: " << e.what() << "\n";
        return 2;
    } catch (const std::exception& e) {
        err << "vsculpt: error: " << e.what() << "\n";
        return 1;
    }
}

}  // namespace vsculpt::app
