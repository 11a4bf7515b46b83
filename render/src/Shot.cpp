// SPDX-License-Identifier: MIT
#include "vsculpt/render/Shot.h"

#include "vsculpt/core/WriteFileAtomically.h"

#include "GlCommon.h"

#include <png.h>

#include <glm/gtc/type_ptr.hpp>

#include <cmath>
#include <cstdio>
#include <memory>

namespace vsculpt::render {

void requireDisplay() {
    detail::ensureGlfw();
}

const char* toString(StereoMode m) {
    switch (m) {
        case StereoMode::Mono:
            return "mono";
        case StereoMode::SideBySide:
            return "sbs";
        case StereoMode::Anaglyph:
            return "anaglyph";
    }
    return "?";
}

StereoMode parseStereoMode(const std::string& s) {
    if (s == "mono") return StereoMode::Mono;
    if (s == "sbs") return StereoMode::SideBySide;
    if (s == "anaglyph") return StereoMode::Anaglyph;
    throw std::invalid_argument("unknown stereo mode '" + s + "' (use mono, sbs or anaglyph)");
}

Image renderShot(const core::Mesh& mesh, const ShotOptions& o) {
    if (o.width < kMinImageSide || o.height < kMinImageSide || o.width > kMaxImageSide ||
        o.height > kMaxImageSide)
        throw RenderError("image size must be between " + std::to_string(kMinImageSide) + " and " +
                          std::to_string(kMaxImageSide) + " pixels per side");
    const detail::WindowPtr window = detail::createWindow(64, 64, "vsculpt shot", false);

    // Offscreen target of the requested size.
    GLuint fbo = 0, color = 0, depth = 0;
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glGenRenderbuffers(1, &color);
    glBindRenderbuffer(GL_RENDERBUFFER, color);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, o.width, o.height);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color);
    glGenRenderbuffers(1, &depth);
    glBindRenderbuffer(GL_RENDERBUFFER, depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, o.width, o.height);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw RenderError("offscreen framebuffer incomplete");

    const GLuint program = detail::clayProgram();

    detail::GpuMesh gpu;
    gpu.upload(mesh);

    const core::Aabb box = core::meshBounds(mesh);
    StereoDisplay d = o.display;
    const bool sbs = o.mode == StereoMode::SideBySide;
    const glm::dmat4 worldFromHead =
        frameFromFront(box.min, box.max, double(sbs ? o.width / 2 : o.width) / o.height, d, o.fit);
    if (o.mode == StereoMode::Mono) d.ipdMm = 0;
    const auto eyes = stereoEyes(worldFromHead, d);

    glEnable(GL_DEPTH_TEST);
    glClearColor(kBackground[0] / 255.f, kBackground[1] / 255.f, kBackground[2] / 255.f, 1.f);
    glViewport(0, 0, o.width, o.height);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glUseProgram(program);
    const GLint clipLoc = glGetUniformLocation(program, "clipFromWorld");
    const GLint eyeLoc = glGetUniformLocation(program, "eye");
    const glm::mat4 identity(1.f);
    glUniformMatrix4fv(glGetUniformLocation(program, "worldFromObject"), 1, GL_FALSE,
                       glm::value_ptr(identity));
    glUniform3f(glGetUniformLocation(program, "tint"), 1.f, 1.f, 1.f);
    const int eyeCount = o.mode == StereoMode::Mono ? 1 : 2;
    for (int e = 0; e < eyeCount; ++e) {
        const EyeView& eye = eyes[size_t(e)];
        if (sbs) glViewport(e == 0 ? 0 : o.width / 2, 0, o.width / 2, o.height);
        if (o.mode == StereoMode::Anaglyph) {
            // Left eye in red, right eye in green and blue (red/cyan glasses).
            if (e == 0)
                glColorMask(GL_TRUE, GL_FALSE, GL_FALSE, GL_TRUE);
            else
                glColorMask(GL_FALSE, GL_TRUE, GL_TRUE, GL_TRUE);
            glClear(GL_DEPTH_BUFFER_BIT);
        }
        const glm::mat4 clip(eye.clipFromView * eye.viewFromWorld);
        glUniformMatrix4fv(clipLoc, 1, GL_FALSE, glm::value_ptr(clip));
        glUniform3f(eyeLoc, float(eye.worldPosition.x), float(eye.worldPosition.y),
                    float(eye.worldPosition.z));
        gpu.draw();
    }
    glFinish();
    detail::checkGl("renderShot");

    Image img;
    img.width = o.width;
    img.height = o.height;
    img.rgba.resize(size_t(o.width) * o.height * 4);
    std::vector<uint8_t> rows(img.rgba.size());
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, o.width, o.height, GL_RGBA, GL_UNSIGNED_BYTE, rows.data());
    for (int y = 0; y < o.height; ++y)  // GL's first row is the bottom one
        std::copy_n(rows.data() + size_t(o.height - 1 - y) * o.width * 4, size_t(o.width) * 4,
                    img.rgba.data() + size_t(y) * o.width * 4);

    gpu.release();
    glDeleteProgram(program);
    glDeleteRenderbuffers(1, &color);
    glDeleteRenderbuffers(1, &depth);
    glDeleteFramebuffers(1, &fbo);
    glfwMakeContextCurrent(nullptr);
    return img;
}

namespace {

// libpng writes through this callback into memory; the file is then written in one piece.
void appendToString(png_structp png, png_bytep data, png_size_t length) {
    static_cast<std::string*>(png_get_io_ptr(png))
        ->append(reinterpret_cast<const char*>(data), length);
}

void noFlush(png_structp) {}

}  // namespace

void writePng(const Image& image, const std::filesystem::path& path) {
    std::string bytes;
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    if (!png || !info || setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        throw RenderError(path.string() + ": PNG encoding failed");
    }
    png_set_write_fn(png, &bytes, appendToString, noFlush);
    png_set_IHDR(png, info, png_uint_32(image.width), png_uint_32(image.height), 8,
                 PNG_COLOR_TYPE_RGBA, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (int y = 0; y < image.height; ++y)
        png_write_row(png, image.rgba.data() + size_t(y) * image.width * 4);
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    // The same atomic writer as projects and exports: a unique temporary name that is never
    // a planted link, renamed into place once complete.
    try {
        core::writeFileAtomically(path, bytes, false);
    } catch (const std::exception& e) {
        throw RenderError(e.what());
    }
}

}  // namespace vsculpt::render
