// SPDX-License-Identifier: MIT
#include "vsculpt/app/CliChecks.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <stdexcept>

#include <spdlog/spdlog.h>

namespace vsculpt::app {

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

void requirePngPath(const std::filesystem::path& path, const std::string& option) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    if (ext != ".png")
        throw std::invalid_argument(option + " " + path.string() +
                                    ": images are written as PNG; name the file .png");
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
