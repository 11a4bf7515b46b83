// SPDX-License-Identifier: MIT
#include "vsculpt/app/CliChecks.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include <spdlog/spdlog.h>

namespace vsculpt::app {

namespace fs = std::filesystem;

std::pair<int, int> parseImageSize(const std::string& text, const std::string& option) {
    int w = 0, h = 0, used = 0;
    char x = 0;
    const bool parsed = std::sscanf(text.c_str(), "%d%c%d%n", &w, &x, &h, &used) == 3 && x == 'x' &&
                        size_t(used) == text.size();
    if (!parsed)
        throw std::invalid_argument(option + " must be WIDTHxHEIGHT (e.g. 1280x800), got '" + text +
                                    "'");
    // What the renderers draw: checked here, before the meshing a run does first.
    if (w < render::kMinImageSide || h < render::kMinImageSide || w > render::kMaxImageSide ||
        h > render::kMaxImageSide)
        throw std::invalid_argument(option + " " + text + ": width and height must be " +
                                    std::to_string(render::kMinImageSide) + " to " +
                                    std::to_string(render::kMaxImageSide) + " pixels");
    return {w, h};
}

namespace {

// `path` ends in `ext` (any case), else std::invalid_argument: "OPTION PATH: WHY".
void requireExtension(const std::filesystem::path& path, const char* ext, const std::string& option,
                      const char* why) {
    std::string got = path.extension().string();
    std::transform(got.begin(), got.end(), got.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    if (got != ext) throw std::invalid_argument(option + " " + path.string() + ": " + why);
}

}  // namespace

void requirePngPath(const std::filesystem::path& path, const std::string& option) {
    requireExtension(path, ".png", option, "images are written as PNG; name the file .png");
}

void requireRecordingPath(const std::filesystem::path& path, const std::string& option) {
    requireExtension(path, ".vsrec", option,
                     "device recordings are written as .vsrec; name the file .vsrec");
}

namespace {

/// Whether two existing paths name one file: the same device and inode, so a hard link too
/// (false when either does not exist).
bool sameFile(const fs::path& a, const fs::path& b) {
    std::error_code ec;
    return fs::equivalent(a, b, ec) && !ec;
}

fs::path resolvedPath(const std::string& path) {
    std::error_code ec;
    const fs::path absolute = fs::absolute(path, ec);
    if (ec) return fs::path(path).lexically_normal();
    const fs::path resolved = fs::weakly_canonical(absolute, ec);
    return ec ? absolute.lexically_normal() : resolved;
}

}  // namespace

std::string outputClash(const std::vector<std::pair<std::string, std::string>>& written,
                        const std::string& script, const std::string& config,
                        const std::string& projectDir) {
    for (size_t i = 0; i < written.size(); ++i) {
        const auto& [option, path] = written[i];
        const fs::path p = resolvedPath(path);
        for (size_t k = 0; k < i; ++k)
            if (resolvedPath(written[k].second) == p)
                return option + " " + path + ": the same file as " + written[k].first + " " +
                       written[k].second + " (each output needs its own file)";
        // By name, and by identity: a hard link names the same file under another name, and a
        // recording is written into the file it finds (found by QA: --record onto a hard link
        // of the project's snapshot destroyed the snapshot).
        if (!script.empty() && (p == resolvedPath(script) || sameFile(p, script)))
            return option + " " + path +
                   ": that is the script being played; it would be overwritten";
        if (!config.empty() && (p == resolvedPath(config) || sameFile(p, config)))
            return option + " " + path + ": that is the --config file; it would be overwritten";
        if (!projectDir.empty() && p.parent_path() == resolvedPath(projectDir)) {
            const fs::path exports = fs::path(projectDir) / "exports";
            std::error_code ec;
            return option + " " + path + ": inside the project folder " + projectDir +
                   ", which holds the project's own files (write it to another folder, such as " +
                   exports.string() +
                   (fs::is_directory(exports, ec) ? "" : ", made first with mkdir") + ")";
        }
        if (std::error_code ec; !projectDir.empty() && fs::is_regular_file(p, ec))
            for (const fs::directory_entry& e : fs::directory_iterator(projectDir, ec))
                if (e.is_regular_file(ec) && sameFile(p, e.path()))
                    return option + " " + path + ": that is the project's " +
                           e.path().filename().string() +
                           " under another name (a hard link); it would be overwritten";
    }
    return "";
}

bool keepLastFrame(render::Viewer& viewer, const std::string& shotPath, render::Image* lastFrame) {
    if (shotPath.empty() && !lastFrame) return true;
    const render::Image img = viewer.readFrame();
    if (lastFrame) *lastFrame = img;
    if (shotPath.empty()) return true;
    try {
        render::writePng(img, shotPath);
        spdlog::info("wrote {}", shotPath);
        return true;
    } catch (const std::exception& e) {
        spdlog::error("{}", e.what());
        return false;
    }
}

}  // namespace vsculpt::app
