// SPDX-License-Identifier: MIT
/// @file Shot.h
/// @brief Renders a mesh with a real OpenGL context (a hidden GLFW window and an offscreen
/// framebuffer) in mono, side-by-side stereo or red/cyan anaglyph, and writes PNG files.
/// Under Xvfb with Mesa (llvmpipe) it works on machines without a GPU.
#pragma once

#include "vsculpt/core/Mesh.h"
#include "vsculpt/render/StereoCamera.h"

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace vsculpt::render {

/// No display, no GL context, or a GL error; the message says which and what to do.
class RenderError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

enum class StereoMode { Mono, SideBySide, Anaglyph };
const char* toString(StereoMode m);
/// "mono", "sbs", "anaglyph"; throws std::invalid_argument for anything else.
StereoMode parseStereoMode(const std::string& name);

struct Image {
    int width = 0, height = 0;
    std::vector<uint8_t> rgba;  ///< top row first
    const uint8_t* pixel(int x, int y) const { return &rgba[(size_t(y) * width + x) * 4]; }
};

struct ShotOptions {
    int width = 960, height = 540;  ///< the whole image (both eyes for side-by-side)
    StereoMode mode = StereoMode::Mono;
    StereoDisplay display;            ///< IPD etc.; fov, aspect and focal distance are set here
    FrameFit fit = FrameFit::Sphere;  ///< the window's framing, as `play --shot` shows it
};

/// The image sizes renderShot and rayTrace draw, per side in pixels (the CLI checks the same
/// bounds before anything runs).
inline constexpr int kMinImageSide = 16, kMaxImageSide = 8192;

/// The RGB of the background (so tests and tools can tell the sculpture from it).
inline constexpr uint8_t kBackground[3] = {26, 28, 38};

/// Frames the mesh from the front (-y looking +y, z up) at a distance that fits it as
/// `options.fit` says (frameFromFront), with the zero-parallax plane through its centre.
/// Object space = world space.
Image renderShot(const core::Mesh& mesh, const ShotOptions& options);

/// Throws RenderError, saying what to do, when no display can be opened for OpenGL: the check
/// renderShot makes first, for a run that must know before its work (`play --shot`).
void requireDisplay();

/// Throws RenderError naming the path when it cannot be written.
void writePng(const Image& image, const std::filesystem::path& path);

}  // namespace vsculpt::render
