// SPDX-License-Identifier: MIT
#include "vsculpt/app/Cli.h"

#include "vsculpt/app/DeviceCommands.h"
#include "vsculpt/app/Log.h"
#include "vsculpt/app/Play.h"
#include "vsculpt/app/RenderStill.h"
#include "vsculpt/app/SketchWindow.h"
#include "vsculpt/app/Summary.h"
#include "vsculpt/app/Window.h"
#include "vsculpt/core/Config.h"
#include "vsculpt/core/NearestName.h"
#include "vsculpt/core/Sculpture.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <iostream>
#include <iterator>
#include <ostream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace vsculpt::app {

namespace {

// The subcommand or long option (of the program or any subcommand) closest to `typed`, when
// it is close enough to be a typo (two edits, or a third of its letters); "" otherwise.
std::string nearestName(const CLI::App& cli, const std::string& typed) {
    std::vector<std::string> names;
    auto addOptions = [&](const CLI::App& app) {
        for (const CLI::Option* o : app.get_options())
            for (const std::string& n : o->get_lnames())
                names.push_back("--" + n);
    };
    addOptions(cli);
    for (const CLI::App* sub : cli.get_subcommands({})) {
        names.push_back(sub->get_name());
        addOptions(*sub);
    }
    return core::nearestName(typed, names);
}

// A number in [lo, hi] (with `unit` in the message). CLI11's own range checks print their
// bounds with std::to_string: "0.000000 to 1797693134862315708145...", 309 digits.
CLI::Validator numberIn(double lo, double hi, const std::string& unit, bool loOpen = false) {
    char text[160];
    std::snprintf(text, sizeof text, "%s%.12g to %.12g%s", loOpen ? "more than " : "", lo, hi,
                  unit.empty() ? "" : (" " + unit).c_str());
    const std::string range = text;
    return CLI::Validator(
        [=](std::string& value) -> std::string {
            double v = 0;
            size_t used = 0;
            try {
                v = std::stod(value, &used);
            } catch (const std::out_of_range&) {
                return "'" + value + "' is out of range: give " + range;  // 1e999, 1e-999
            } catch (const std::exception&) {
                used = 0;
            }
            if (used != value.size() || used == 0) return "'" + value + "' is not a number";
            if (!(loOpen ? v > lo : v >= lo) || !(v <= hi))
                return "'" + value + "' is out of range: give " + range;
            return "";
        },
        range);
}

// `word` itself, or what `other` accepts.
CLI::Validator orWord(const std::string& word, CLI::Validator other) {
    const std::string description = other.get_description() + " or " + word;
    return CLI::Validator(
        [word, other](std::string& value) mutable -> std::string {
            if (value == word) return "";
            const std::string why = other(value);
            return why.empty() ? why : why + " (or " + word + ")";
        },
        description);
}

}  // namespace

int runCli(int argc, const char* const* argv, std::ostream& out, std::ostream& err) {
    // `vsculpt help [SUBCOMMAND]`, as git and cargo take it: the subcommand's --help (found by
    // QA: "SCRIPT is required").
    std::vector<const char*> helpArgs;
    if (argc >= 2 && argc <= 3 && std::string(argv[1]) == "help") {
        helpArgs = {argv[0]};
        if (argc == 3) helpArgs.push_back(argv[2]);
        helpArgs.push_back("--help");
        argc = int(helpArgs.size());
        argv = helpArgs.data();
    }
    CLI::App cli{
        "vsculpt - immersive virtual-sculpting modeler.\n"
        "Without a subcommand it opens the sculpting window (docs/window.md: mouse and keys\n"
        "stand in for the pen and the 3D mouse); without a display it says so and prints the\n"
        "summary of `vsculpt info`. `vsculpt play` runs a playback script headless\n"
        "(docs/playback.md), `vsculpt render` ray-traces a still. `vsculpt devices` lists the\n"
        "trackers, 3D mice, tablets and headsets vsculpt can use, `vsculpt record` sculpts with\n"
        "them while recording every report; `vsculpt play` replays such a recording\n"
        "(docs/devices.md). `vsculpt sketch` opens the sketch window: a pen-tablet canvas\n"
        "beside the sculpture, sketches turned into solids in it (docs/sketch-mode.md).\n"
        "Both windows save every step to a project as it is made: --project DIR, else the\n"
        "last project or a new one under ~/.local/share/vsculpt (docs/projects.md).\n"
        "What is not built yet: generic HID pen tablets are read through hidraw only (not\n"
        "with access \"libusb\")."};
    cli.set_version_flag("--version", "vsculpt 0.1.0");
    std::string configPath = core::defaultConfigPath().string();
    // `--project "$DIR"` or `--config "$CFG"` with the variable unset would otherwise run
    // without the project or the settings meant (found by QA: the defaults, in silence).
    const CLI::Validator notEmpty(
        [](std::string& value) -> std::string {
            return value.empty() ? "must not be empty (an unset shell variable?)" : "";
        },
        "");
    cli.add_option("--config", configPath,
                   "Config file (JSON with comments; docs/config.md). Default: $VSCULPT_CONFIG, "
                   "else $XDG_CONFIG_HOME/vsculpt/sculpt.json (~/.config/vsculpt/sculpt.json) if "
                   "it exists, else the built-in defaults")
        ->check(notEmpty);

    bool quiet = false;
    int verbose = 0;
    auto* quietFlag = cli.add_flag("-q,--quiet", quiet,
                                   "Only errors and warnings: no progress bars, no summaries");
    cli.add_flag("-v,--verbose", verbose,
                 "Also debug messages (configuration used, timings); twice: trace messages")
        ->excludes(quietFlag);

    WindowOptions window;
    cli.add_option(
           "--stereo", window.stereo,
           "Window stereo mode: mono, sbs or anaglyph (default: the config's render.stereo)")
        ->check(CLI::IsMember({"mono", "sbs", "anaglyph"}));
    cli.add_option("--frames", window.frames, "Close the window after N frames (0: never)")
        ->check(numberIn(0, 1e9, "frames"));
    cli.add_option("--play", window.playScript,
                   "Run a playback script in the window, a command per frame");
    cli.add_option("--shot", window.shotPath,
                   "Save the last frame as PNG (after --frames N frames; alone: one frame)");
    cli.add_flag("--hidden", window.hidden, "Do not show the window (automated runs)");
    cli.add_flag_callback(
        "--no-devices", [&window] { window.devices = false; },
        "Do not open trackers, 3D mice or headsets (mouse and keyboard only)");
    auto* windowProject =
        cli.add_option(
               "--project", window.projectDir,
               "Project folder for the window: opened (and recovered) if it exists, created "
               "otherwise. Default: the last project, or a new autosave project under "
               "$XDG_DATA_HOME/vsculpt/autosave; every step is journaled as it is made")
            ->check(notEmpty);
    bool xr = false;
    cli.add_flag("--xr", xr,
                 "Sculpt in an OpenXR headset (Monado, SteamVR; docs/xr.md): right controller = "
                 "pen, left = 3D mouse. Without a runtime or headset: a warning, then the window");
    cli.add_option("--record", window.recordPath,
                   "With --xr: record the controllers to FILE.vsrec, a report a frame (replay: "
                   "vsculpt play FILE)");
    cli.add_flag("--no-project", window.noProject,
                 "A scratch session: nothing is saved (the window's work is lost on exit)")
        ->excludes(windowProject);
    CLI::App* infoCmd = cli.add_subcommand(
        "info", "Print the initial sculpture's summary: tool levels, calibration, mesh");

    PlayOptions play;
    CLI::App* playCmd = cli.add_subcommand(
        "play", "Run a playback script headless: sculpt, export, report (docs/playback.md)");
    playCmd
        ->add_option("SCRIPT", play.script, "Playback script (.vsc) or device recording (.vsrec)")
        ->required();
    playCmd->add_option("--out", play.outputs,
                        "Export the final sculpture; repeatable; format from the extension: "
                        ".obj .stl .ply .glb .dxf .vdb");
    playCmd
        ->add_option("--up", play.up,
                     "Up axis of the --out files, y or z (default: y for .obj, z for .stl .ply "
                     ".dxf .vdb; .glb is always y; docs/playback.md)")
        ->check(CLI::IsMember({"y", "z"}, CLI::ignore_case));
    playCmd
        ->add_option("--units", play.units,
                     "Length unit of the --out files, mm, cm or m (default: mm; .glb is always m)")
        ->check(CLI::IsMember({"mm", "cm", "m"}, CLI::ignore_case));
    playCmd->add_option("--stats", play.statsPath, "Write statistics as JSON to PATH (- = stdout)");
    playCmd->add_flag("--check", play.check,
                      "After every edit, compare the incremental mesh with a full rebuild");
    playCmd->add_option("--threads", play.threads, "Worker threads (default: all cores)")
        ->check(numberIn(1, 256, "threads"));
    playCmd
        ->add_option("--project", play.projectDir,
                     "Project folder: opened (and recovered) if it exists, created otherwise; "
                     "every edit is journaled")
        ->check(notEmpty);
    playCmd
        ->add_option_function<std::string>(
            "--export-spacing",
            [&play](const std::string& v) {
                play.exportSpacingMm =
                    v == "detail" ? PlayOptions::kExportSpacingDetail : std::stod(v);
            },
            "Grid spacing in mm for exports and statistics, or 'detail': the spacing that keeps "
            "the finest detail sculpted, as the windows' export takes it (default: zoom 1's; "
            "an export that loses finer detail says which spacing keeps it)")
        ->type_name("MM|detail")
        ->check(orWord("detail", numberIn(0, PlayOptions::kMaxExportSpacingMm, "mm",
                                          /*loOpen=*/true)));
    playCmd->add_flag_callback(
        "--no-progress", [&play] { play.progress = false; }, "No progress bar");
    playCmd->add_option("--shot", play.shotPath,
                        "Render the final frame with OpenGL to a PNG (needs a display; "
                        "use xvfb-run on machines without one)");
    playCmd->add_option("--stereo", play.stereo, "Stereo mode of --shot: mono, sbs or anaglyph")
        ->check(CLI::IsMember({"mono", "sbs", "anaglyph"}))
        ->capture_default_str();
    playCmd->add_option("--shot-size", play.shotSize, "Size of --shot, WIDTHxHEIGHT")
        ->capture_default_str();

    CLI::App* devicesCmd = cli.add_subcommand(
        "devices",
        "List connected trackers, 3D mice, tablets and headsets and whether vsculpt can use them");
    RecordOptions record;
    CLI::App* recordCmd = cli.add_subcommand("record",
                                             "Sculpt headless with the connected devices and "
                                             "record every raw report (replay: vsculpt play FILE)");
    recordCmd->add_option("--out", record.outPath, "Recording to write (.vsrec)")->required();
    recordCmd
        ->add_option("--seconds", record.seconds, "Stop after this many seconds (default: Ctrl-C)")
        ->check(numberIn(0, 1e7, "seconds"));
    recordCmd->add_flag("--until-unplugged", record.untilUnplugged,
                        "Stop once every device that connected has been unplugged again");

    SketchWindowOptions sketchOpts;
    CLI::App* sketchCmd = cli.add_subcommand(
        "sketch",
        "Open the sketch window: a pen-tablet canvas beside the sculpture; sketches become "
        "solids in it (docs/sketch-mode.md)");
    auto* sketchProject =
        sketchCmd
            ->add_option("--project", sketchOpts.projectDir,
                         "Project folder: opened if it exists, created otherwise; every "
                         "sketch and sculpt step is saved as it is made. Default: the last "
                         "project, or a new autosave project")
            ->check(notEmpty);
    sketchCmd->add_flag("--no-project", sketchOpts.noProject, "A scratch session: nothing is saved")
        ->excludes(sketchProject);
    sketchCmd->add_option("--play", sketchOpts.playScript,
                          "Run a playback script (sketch commands too) in the window, a command "
                          "per frame");
    sketchCmd->add_option("--frames", sketchOpts.frames, "Close after N frames (0: never)")
        ->check(numberIn(0, 1e9, "frames"));
    sketchCmd->add_option("--shot", sketchOpts.shotPath,
                          "With --frames: save the last frame as PNG");
    sketchCmd->add_flag("--hidden", sketchOpts.hidden, "Do not show the window (automated runs)");
    sketchCmd->add_flag("--headset", sketchOpts.headset,
                        "Also show the sculpture in side-by-side stereo for the headset (full "
                        "screen on the config's render.fullscreen_monitor)");
    sketchCmd->add_flag_callback(
        "--no-devices", [&sketchOpts] { sketchOpts.devices = false; },
        "Do not open pen tablets or other devices (mouse and keyboard only)");

    RenderOptions still;
    CLI::App* renderCmd = cli.add_subcommand(
        "render", "Ray-trace a still of a script's or a project's sculpture (Embree)");
    renderCmd
        ->add_option("INPUT", still.input,
                     "Playback script or project folder (opened read-only: never changed)")
        ->required();
    renderCmd->add_option("--out", still.outPath, "PNG to write")->required();
    renderCmd->add_option("--size", still.size, "Image size WIDTHxHEIGHT")->capture_default_str();
    renderCmd->add_option("--samples", still.samples, "Ambient-occlusion rays per pixel")
        ->check(numberIn(1, 1024, "rays"))
        ->capture_default_str();
    renderCmd
        ->add_option("--spacing", still.spacingMm,
                     "Mesh grid spacing in mm (default: zoom 3's, for fine detail)")
        ->check(numberIn(0, RenderOptions::kMaxSpacingMm, "mm", /*loOpen=*/true));
    renderCmd
        ->add_option("--yaw", still.yawDeg,
                     "Camera: turn the sculpture about the vertical (z) axis, degrees")
        ->check(numberIn(-3600, 3600, "degrees"));
    renderCmd
        ->add_option("--pitch", still.pitchDeg,
                     "Camera: tilt the sculpture about the horizontal (x) axis, degrees")
        ->check(numberIn(-3600, 3600, "degrees"));
    renderCmd
        ->add_option("--turntable", still.turntable,
                     "Render N frames of one turn about the vertical axis (one framing), to "
                     "--out with the frame number: a run of '#' in the name, else -NNN before "
                     "the extension (turn.png: turn-000.png ...)")
        ->check(numberIn(1, 3600, "frames"));
    renderCmd->add_flag_callback(
        "--no-progress", [&still] { still.progress = false; }, "No progress bar");

    // --config is the program's, accepted before or after any subcommand (and never ignored):
    // an option a subcommand does not know falls through to the program.
    for (CLI::App* sub : {infoCmd, playCmd, devicesCmd, recordCmd, sketchCmd, renderCmd}) {
        sub->fallthrough();
        sub->footer(
            "The program's options (--config, -q, -v) go before or after the subcommand; "
            "`vsculpt --help` lists them.");
    }

    try {
        cli.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // Help and version: CLI11 prints them to out. Usage errors: to err, in the form of
        // every other message ("vsculpt: error: ..."), exit code 2.
        if (e.get_exit_code() == 0) return cli.exit(e, out, err);
        const int code = 2;
        // A mistyped subcommand or option (not a bad value of a real one): name the nearest.
        const bool unknownWord = dynamic_cast<const CLI::ExtrasError*>(&e) != nullptr;
        if (unknownWord) {
            // The words in the order they were typed (CLI11 lists them last first), and the
            // likely reason when they are more scripts for play.
            const std::string what = e.what();
            const size_t colon = what.find(": ");
            std::istringstream listed(colon == std::string::npos ? "" : what.substr(colon + 2));
            std::set<std::string> extra{std::istream_iterator<std::string>(listed), {}};
            std::string words;
            bool scripts = false;
            for (int i = 1; i < argc; ++i)
                if (extra.count(argv[i])) {
                    words += std::string(words.empty() ? "" : " ") + argv[i];
                    const std::string ext = std::filesystem::path(argv[i]).extension().string();
                    scripts |= ext == ".vsc" || ext == ".vsrec";
                }
            err << "vsculpt: error: unexpected argument(s): " << (words.empty() ? what : words)
                << (scripts && *playCmd ? " (vsculpt play takes one SCRIPT a run)" : "")
                << "\nRun with --help for more information.\n";
        } else {
            err << "vsculpt: error: " << e.what() << "\nRun with --help for more information.\n";
        }
        if (unknownWord) {
            for (int i = 1; i < argc; ++i) {
                const std::string arg = argv[i];
                if (std::string(e.what()).find(arg) == std::string::npos) continue;
                if (const std::string near = nearestName(cli, arg); !near.empty()) {
                    err << "vsculpt: did you mean '" << near << "'?\n";
                    break;
                }
            }
        }
        return code;
    }

    const Verbosity verbosity = quiet          ? Verbosity::Quiet
                                : verbose >= 2 ? Verbosity::Trace
                                : verbose == 1 ? Verbosity::Verbose
                                               : Verbosity::Normal;
    LogScope log(err, verbosity);
    play.verbosity = verbosity;
    still.verbosity = verbosity;
    record.verbosity = verbosity;
    window.verbosity = verbosity;
    sketchOpts.verbosity = verbosity;

    const std::string givenConfig = cli.count("--config") > 0 ? configPath : "";
    play.configPath = givenConfig;
    still.configPath = givenConfig;
    if (*playCmd) return runPlay(play, out, err);
    if (*devicesCmd) return runDevices(configPath, out, err, verbosity);
    if (*recordCmd) {
        record.configPath = configPath;
        return runRecord(record, out, err);
    }
    if (*renderCmd) return runRenderStill(still, out, err);
    if (*sketchCmd) {
        sketchOpts.configPath = configPath == core::defaultConfigPath().string() ? "" : configPath;
        return runSketchWindow(sketchOpts, out, err);
    }
    if (xr) window.xr = true;
    if (!*infoCmd) {
        window.configPath = configPath == core::defaultConfigPath().string() ? "" : configPath;
        const int code = runWindow(window, out, err);
        // Without a display the summary stands in for the window, unless the window was asked
        // for work (a script, a shot, frames): that work was not done, so it is a failure. A
        // headset session (--xr, render.output "xr") reports its own failures (a lost headset).
        bool headset = xr;
        if (!headset && code == 1) {
            try {
                headset = core::loadConfig(configPath).render.output == "xr";
            } catch (const std::exception&) {
                // A bad config was reported (exit 2) before any headset was opened.
            }
        }
        const bool askedForWindowWork =
            !window.shotPath.empty() || !window.playScript.empty() || window.frames > 0;
        if (code != 1 || askedForWindowWork || headset) return code;
        // No display: the summary is the headless main job.
    }

    try {
        const core::SculptConfig cfg = core::loadConfig(configPath);
        const core::Sculpture sculpture(cfg);
        printSummary(sculpture, out);
        return 0;
    } catch (const core::ConfigError& e) {
        spdlog::error("{}", e.what());
        return 2;
    } catch (const std::exception& e) {
        spdlog::error("{}", e.what());
        return 1;
    }
}

}  // namespace vsculpt::app

namespace vsculpt::app {

int standardOutputChecked(int code) {
    errno = 0;
    std::cout.flush();
    const bool flushed = std::fflush(stdout) == 0;
    const int why = errno;
    if (std::cout && flushed && !std::ferror(stdout)) return code;
    std::fprintf(stderr, "vsculpt: error: cannot write to standard output: %s\n",
                 why != 0 ? std::strerror(why) : "write error");
    return code == 0 ? 1 : code;
}

}  // namespace vsculpt::app
