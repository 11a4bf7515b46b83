// SPDX-License-Identifier: MIT
#include "vsculpt/render/Viewer.h"

#include "GlCommon.h"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <chrono>
#include <cmath>
#include <map>
#include <numbers>
#include <utility>

namespace vsculpt::render {

namespace {

/// Lines drawn aliased, every sample covered: a one-pixel line multisampled comes out as a
/// faint, broken one (its samples lose depth ties with the surface it lies on).
void drawWholeLines(const detail::GpuMesh& lines) {
    glDisable(GL_MULTISAMPLE);
    lines.draw(GL_LINES);
    glEnable(GL_MULTISAMPLE);
}

/// Lines on the model: lines and triangles rasterize depth differently, so they are pulled a
/// hair nearer, and the surface they lie on does not cut them into dashes.
void drawLinesOnSurface(const detail::GpuMesh& lines) {
    glDepthFunc(GL_LEQUAL);
    glDepthRange(0.0, 0.9995);
    drawWholeLines(lines);
    glDepthRange(0.0, 1.0);
    glDepthFunc(GL_LESS);
}

/// A unit sphere (for the tool), latitude-longitude.
core::Mesh unitSphere(int rings, int segments) {
    core::Mesh m;
    for (int r = 0; r <= rings; ++r) {
        const double th = std::numbers::pi * r / rings;
        for (int s = 0; s <= segments; ++s) {
            const double ph = 2 * std::numbers::pi * s / segments;
            const core::Vec3 p(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph),
                               std::cos(th));
            m.positions.push_back(p);
            m.normals.push_back(p);
        }
    }
    for (int r = 0; r < rings; ++r)
        for (int s = 0; s < segments; ++s) {
            const uint32_t a = uint32_t(r * (segments + 1) + s), b = a + uint32_t(segments + 1);
            for (uint32_t i : {a, b, a + 1, a + 1, b, b + 1})
                m.indices.push_back(i);
        }
    return m;
}

}  // namespace

static const char* kPostVertex = R"(#version 330 core
out vec2 uv;
void main() {
    // One triangle covering the viewport.
    vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
    uv = p;
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
})";

static const char* kPostFragment = R"(#version 330 core
in vec2 uv;
out vec4 color;
uniform sampler2D eyeImage;
uniform vec2 k;        // k1, k2
uniform vec2 scaleRB;  // chromatic aberration: red and blue scales
uniform float aspect;  // eye image width / height
vec2 toUv(vec2 c) { return vec2(c.x / aspect, c.y) * 0.5 + 0.5; }
float channel(vec2 c, int i) {
    vec2 t = toUv(c);
    if (any(lessThan(t, vec2(0.0))) || any(greaterThan(t, vec2(1.0)))) return 0.0;
    return texture(eyeImage, t)[i];
}
void main() {
    vec2 c = uv * 2.0 - 1.0;
    c.x *= aspect;  // in units of the half-height
    float r2 = dot(c, c);
    vec2 d = c * (1.0 + k.x * r2 + k.y * r2 * r2);
    color = vec4(channel(d * scaleRB.x, 0), channel(d, 1), channel(d * scaleRB.y, 2), 1.0);
})";

static const char* kUiVertex = R"(#version 330 core
uniform vec4 rect;    // x0, y0, x1, y1 in NDC
uniform vec4 uvRect;  // the same corners in the UI texture (row 0 at its bottom, as GL draws)
out vec2 uv;
void main() {
    vec2 corner = vec2(gl_VertexID & 1, (gl_VertexID >> 1) & 1);
    uv = mix(uvRect.xy, uvRect.zw, corner);
    gl_Position = vec4(mix(rect.xy, rect.zw, corner), 0.0, 1.0);
})";

static const char* kUiFragment = R"(#version 330 core
in vec2 uv;
uniform sampler2D ui;
out vec4 color;
void main() { color = texture(ui, uv); })";

struct Viewer::Impl {
    detail::WindowPtr window;
    std::optional<glm::dmat4> trackedHead;
    // The columns of the window the 3D view uses (sketch mode puts the canvas beside it);
    // width 0: the whole window. Framebuffer pixels.
    int areaX = 0, areaW = 0;
    // Surface lines drawn on the model (object space), as GL_LINES pairs.
    std::vector<std::vector<core::Vec3>> lines;
    detail::GpuMesh lineMesh;
    int windowSamples = 1;        // of the window's framebuffer
    detail::GpuMesh pointerMesh;  // the headset pen's ray, uploaded per eye (two vertices)
    GLuint uiProgram = 0;
    // The display of the last draw and the UI shift it gave each eye (NDC).
    StereoDisplay lastDisplay;
    double uiShift[2] = {0, 0};
    GLuint postProgram = 0, postVao = 0;
    GLuint eyeFbo = 0, eyeColor = 0, eyeDepth = 0;
    int eyeW = 0, eyeH = 0;
    GLuint program = 0;
    GLint clipLoc = -1, worldFromObjectLoc = -1, eyeLoc = -1, tintLoc = -1;
    const core::Polygonizer* view = nullptr;
    core::GridRegion region;
    std::map<std::array<int, 3>, detail::GpuMesh> chunks;
    detail::GpuMesh sphere;
    std::vector<InputEvent> events;
    EyeView monoEye;
    // Headset eyes (drawEye): a framebuffer for the swapchain texture and its depth.
    GLuint xrFbo = 0, xrDepth = 0;
    bool culling = true;  // chunks wholly outside an eye's view are not drawn
    // Multisampled eyes (setEyeSamples): drawn here, then resolved into the swapchain image.
    int eyeSamples = 1;
    GLuint msFbo = 0, msColor = 0, msDepth = 0;
    int msW = 0, msH = 0, msSamples = 0;
    GLint msFormat = 0;
    GLuint copyFrom = 0, copyTo = 0;  // copyTexture's framebuffers: colour only
    int xrW = 0, xrH = 0;
};

Viewer::Viewer(int width, int height, const std::string& title, bool visible, int samples)
    : mImpl(std::make_unique<Impl>()) {
    // Auto (0) opens hidden first: a window recreated for a software rasterizer would flash.
    mImpl->window = detail::createWindow(width, height, title, visible && samples != 0,
                                         samples > 0 ? samples : 4);
    if (samples == 0) {
        // Auto: a software rasterizer pays for every sample on the CPU (Mesa's llvmpipe drew a
        // window frame in 31 ms with 4 samples against 11 ms with 1): a plain window there.
        const auto* r = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
        const std::string name = r ? r : "";
        if (name.find("llvmpipe") != std::string::npos ||
            name.find("softpipe") != std::string::npos ||
            name.find("Software Rasterizer") != std::string::npos) {
            mImpl->window.reset();
            mImpl->window = detail::createWindow(width, height, title, visible, 1);
        } else if (visible) {
            glfwShowWindow(mImpl->window.get());
        }
    }
    {
        // What the display gave (the default framebuffer is bound now).
        GLint buffers = 0, got = 0;
        glGetIntegerv(GL_SAMPLE_BUFFERS, &buffers);
        glGetIntegerv(GL_SAMPLES, &got);
        mImpl->windowSamples = buffers > 0 ? std::max(1, int(got)) : 1;
    }
    GLFWwindow* w = mImpl->window.get();
    glfwSetWindowUserPointer(w, mImpl.get());
    glfwSetKeyCallback(w, [](GLFWwindow* win, int key, int, int action, int) {
        if (action == GLFW_REPEAT) return;
        static_cast<Impl*>(glfwGetWindowUserPointer(win))
            ->events.push_back({InputEvent::Kind::Key, key, action == GLFW_PRESS, 0, 0});
    });
    glfwSetMouseButtonCallback(w, [](GLFWwindow* win, int button, int action, int) {
        static_cast<Impl*>(glfwGetWindowUserPointer(win))
            ->events.push_back({InputEvent::Kind::MouseButton, button, action == GLFW_PRESS, 0, 0});
    });
    glfwSetCursorPosCallback(w, [](GLFWwindow* win, double x, double y) {
        static_cast<Impl*>(glfwGetWindowUserPointer(win))
            ->events.push_back({InputEvent::Kind::Cursor, 0, false, x, y});
    });
    glfwSetScrollCallback(w, [](GLFWwindow* win, double dx, double dy) {
        static_cast<Impl*>(glfwGetWindowUserPointer(win))
            ->events.push_back({InputEvent::Kind::Scroll, 0, false, dx, dy});
    });
    glfwSetCharCallback(w, [](GLFWwindow* win, unsigned int codepoint) {
        static_cast<Impl*>(glfwGetWindowUserPointer(win))
            ->events.push_back({InputEvent::Kind::Char, int(codepoint), true, 0, 0});
    });
    mImpl->program = detail::clayProgram();
    mImpl->clipLoc = glGetUniformLocation(mImpl->program, "clipFromWorld");
    mImpl->worldFromObjectLoc = glGetUniformLocation(mImpl->program, "worldFromObject");
    mImpl->eyeLoc = glGetUniformLocation(mImpl->program, "eye");
    mImpl->tintLoc = glGetUniformLocation(mImpl->program, "tint");
    mImpl->sphere.upload(unitSphere(16, 32));
    mImpl->postProgram = detail::linkProgram(kPostVertex, kPostFragment);
    mImpl->uiProgram = detail::linkProgram(kUiVertex, kUiFragment);
    glGenVertexArrays(1, &mImpl->postVao);
    glfwSwapInterval(0);
    detail::checkGl("Viewer setup");
}

Viewer::~Viewer() {
    if (!mImpl->window) return;
    glfwMakeContextCurrent(mImpl->window.get());
    for (auto& [k, c] : mImpl->chunks)
        c.release();
    mImpl->sphere.release();
    mImpl->lineMesh.release();
    mImpl->pointerMesh.release();
    glDeleteProgram(mImpl->program);
    glDeleteProgram(mImpl->postProgram);
    glDeleteProgram(mImpl->uiProgram);
    glDeleteVertexArrays(1, &mImpl->postVao);
    if (mImpl->eyeFbo) {
        glDeleteFramebuffers(1, &mImpl->eyeFbo);
        glDeleteTextures(1, &mImpl->eyeColor);
        glDeleteRenderbuffers(1, &mImpl->eyeDepth);
    }
    if (mImpl->xrFbo) {
        glDeleteFramebuffers(1, &mImpl->xrFbo);
        glDeleteRenderbuffers(1, &mImpl->xrDepth);
    }
    if (mImpl->msFbo) {
        glDeleteFramebuffers(1, &mImpl->msFbo);
        glDeleteRenderbuffers(1, &mImpl->msColor);
        glDeleteRenderbuffers(1, &mImpl->msDepth);
    }
    if (mImpl->copyFrom) {
        glDeleteFramebuffers(1, &mImpl->copyFrom);
        glDeleteFramebuffers(1, &mImpl->copyTo);
    }
}

void Viewer::injectEvent(const InputEvent& event) {
    mImpl->events.push_back(event);
}

std::vector<InputEvent> Viewer::pollEvents() {
    glfwPollEvents();
    if (glfwWindowShouldClose(mImpl->window.get())) {
        mImpl->events.push_back({InputEvent::Kind::Close, 0, true, 0, 0});
        glfwSetWindowShouldClose(mImpl->window.get(), GLFW_FALSE);
    }
    return std::exchange(mImpl->events, {});
}

void Viewer::setTitle(const std::string& title) {
    glfwSetWindowTitle(mImpl->window.get(), title.c_str());
}

int Viewer::width() const {
    int w = 0, h = 0;
    glfwGetFramebufferSize(mImpl->window.get(), &w, &h);
    return w;
}

int Viewer::height() const {
    int w = 0, h = 0;
    glfwGetFramebufferSize(mImpl->window.get(), &w, &h);
    return h;
}

size_t Viewer::syncChunks(const core::Polygonizer& view) {
    if (mImpl->view != &view || !(mImpl->region == view.region())) {
        for (auto& [k, c] : mImpl->chunks)
            c.release();
        mImpl->chunks.clear();
        mImpl->view = &view;
        mImpl->region = view.region();
    }
    size_t uploads = 0;
    const int n = view.chunksPerAxis();
    for (int x = 0; x < n; ++x)
        for (int y = 0; y < n; ++y)
            for (int z = 0; z < n; ++z) {
                const uint64_t version = view.chunkVersion(x, y, z);
                if (version == 0) continue;  // never had triangles
                auto it = mImpl->chunks.find({x, y, z});
                if (it != mImpl->chunks.end() && it->second.version == version) continue;
                detail::GpuMesh& g = mImpl->chunks[{x, y, z}];
                g.upload(view.chunkMesh(x, y, z));
                g.version = version;
                ++uploads;
            }
    return uploads;
}

size_t Viewer::syncChunks(const core::MeshChunks& set) {
    if (mImpl->view != nullptr || !(mImpl->region == set.region)) {
        for (auto& [k, c] : mImpl->chunks)
            c.release();
        mImpl->chunks.clear();
        mImpl->view = nullptr;
        mImpl->region = set.region;
    }
    size_t uploads = 0;
    const int n = set.chunksPerAxis;
    for (int x = 0; x < n; ++x)
        for (int y = 0; y < n; ++y)
            for (int z = 0; z < n; ++z) {
                const size_t i = set.index(x, y, z);
                auto it = mImpl->chunks.find({x, y, z});
                if (!set.meshes[i]) {
                    if (it != mImpl->chunks.end()) {
                        it->second.release();
                        mImpl->chunks.erase(it);
                    }
                    continue;
                }
                if (it != mImpl->chunks.end() && it->second.version == set.versions[i]) continue;
                detail::GpuMesh& g = mImpl->chunks[{x, y, z}];
                g.upload(*set.meshes[i]);
                g.version = set.versions[i];
                ++uploads;
            }
    return uploads;
}

FrameStats Viewer::draw(const glm::dmat4& worldFromObject, const core::Aabb& frameBox,
                        const ToolDraw& tool, StereoMode mode, const StereoDisplay& displayIn,
                        const LensCorrection& lens, const UiImage* ui) {
    const auto t0 = std::chrono::steady_clock::now();
    FrameStats stats;
    const int fullW = width(), h = height();
    const int x0 = mImpl->areaW > 0 ? std::min(mImpl->areaX, fullW - 1) : 0;
    const int w = mImpl->areaW > 0 ? std::max(1, std::min(mImpl->areaW, fullW - x0)) : fullW;
    StereoDisplay d = displayIn;
    const bool sbs = mode == StereoMode::SideBySide;
    // The camera frames the box (in world space after the object's pose).
    const glm::dvec3 c =
        glm::dvec3(worldFromObject * glm::dvec4(0.5 * (frameBox.min + frameBox.max), 1));
    const glm::dvec3 half = 0.5 * (frameBox.max - frameBox.min);
    // Framing also sets the display's aspect, focal distance and clip planes; a tracked
    // head keeps those and replaces only the pose.
    const glm::dmat4 framedHead =
        frameFromFront(c - half, c + half, double(sbs ? w / 2 : w) / std::max(1, h), d);
    const glm::dmat4 worldFromHead = mImpl->trackedHead.value_or(framedHead);
    if (mode == StereoMode::Mono) d.ipdMm = 0;
    const auto eyes = stereoEyes(worldFromHead, d);
    mImpl->lastDisplay = d;
    for (int e = 0; e < 2; ++e) {
        // Whole pixels: the UI texture then maps 1:1 onto the eye's image and text stays sharp.
        const int eyeW = sbs ? w / 2 : w;
        const double px = ui && mode != StereoMode::Mono
                              ? std::round(eyeShiftNdc(d, ui->depthMm, Eye(e)) * eyeW / 2)
                              : 0.0;
        mImpl->uiShift[e] = 2 * px / std::max(1, eyeW);
    }
    {
        StereoDisplay mono = d;
        mono.ipdMm = 0;
        mono.aspect = double(w) / std::max(1, h);
        mImpl->monoEye = stereoEyes(worldFromHead, mono)[0];
    }
    const bool corrected = sbs && lens.active();
    if (corrected && (mImpl->eyeW != w / 2 || mImpl->eyeH != h)) {
        // An offscreen image per eye, resampled through the lens correction afterwards.
        if (mImpl->eyeFbo) {
            glDeleteFramebuffers(1, &mImpl->eyeFbo);
            glDeleteTextures(1, &mImpl->eyeColor);
            glDeleteRenderbuffers(1, &mImpl->eyeDepth);
        }
        mImpl->eyeW = w / 2;
        mImpl->eyeH = h;
        glGenFramebuffers(1, &mImpl->eyeFbo);
        glBindFramebuffer(GL_FRAMEBUFFER, mImpl->eyeFbo);
        glGenTextures(1, &mImpl->eyeColor);
        glBindTexture(GL_TEXTURE_2D, mImpl->eyeColor);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, mImpl->eyeW, mImpl->eyeH, 0, GL_RGBA,
                     GL_UNSIGNED_BYTE, nullptr);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, mImpl->eyeColor,
                               0);
        glGenRenderbuffers(1, &mImpl->eyeDepth);
        glBindRenderbuffer(GL_RENDERBUFFER, mImpl->eyeDepth);
        glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, mImpl->eyeW, mImpl->eyeH);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                                  mImpl->eyeDepth);
        if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
            throw RenderError("eye framebuffer incomplete");
    }
    const glm::vec3 bg(kBackground[0] / 255.f, kBackground[1] / 255.f, kBackground[2] / 255.f);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(x0, 0, w, h);
    glEnable(GL_DEPTH_TEST);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glClearColor(bg.r, bg.g, bg.b, 1.f);
    // Clear only the 3D view's columns: the rest of the window belongs to others.
    glEnable(GL_SCISSOR_TEST);
    glScissor(x0, 0, w, h);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glDisable(GL_SCISSOR_TEST);
    const glm::mat4 object(worldFromObject);
    for (int e = 0; e < (mode == StereoMode::Mono ? 1 : 2); ++e) {
        const EyeView& eye = eyes[size_t(e)];
        if (corrected) {
            glBindFramebuffer(GL_FRAMEBUFFER, mImpl->eyeFbo);
            glViewport(0, 0, mImpl->eyeW, mImpl->eyeH);
            glEnable(GL_DEPTH_TEST);
            glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        } else if (sbs) {
            glViewport(x0 + (e == 0 ? 0 : w / 2), 0, w / 2, h);
        }
        if (mode == StereoMode::Anaglyph) {
            if (e == 0)
                glColorMask(GL_TRUE, GL_FALSE, GL_FALSE, GL_TRUE);
            else
                glColorMask(GL_FALSE, GL_TRUE, GL_TRUE, GL_TRUE);
            glClear(GL_DEPTH_BUFFER_BIT);
        }
        glUseProgram(mImpl->program);
        const glm::mat4 clip(eye.clipFromView * eye.viewFromWorld);
        glUniformMatrix4fv(mImpl->clipLoc, 1, GL_FALSE, glm::value_ptr(clip));
        glUniform3f(mImpl->eyeLoc, float(eye.worldPosition.x), float(eye.worldPosition.y),
                    float(eye.worldPosition.z));
        glUniformMatrix4fv(mImpl->worldFromObjectLoc, 1, GL_FALSE, glm::value_ptr(object));
        glUniform3f(mImpl->tintLoc, 1.f, 1.f, 1.f);
        const detail::ViewPlanes view(clip * object);
        for (const auto& [k, g] : mImpl->chunks) {
            if (mImpl->culling && view.outside(g.lo, g.hi)) continue;
            g.draw();
            if (e == 0) {
                ++stats.chunksDrawn;
                stats.triangles += size_t(g.count / 3);
            }
        }
        if (mImpl->lineMesh.count > 0) {
            // Surface lines on the model, dark red; they lie exactly on its triangles, so
            // equal depth passes.
            glUniformMatrix4fv(mImpl->worldFromObjectLoc, 1, GL_FALSE, glm::value_ptr(object));
            glUniform3f(mImpl->tintLoc, 0.75f, 0.12f, 0.1f);
            drawLinesOnSurface(mImpl->lineMesh);
        }
        if (tool.visible) {
            // Contact cue: green in the air, yellow touching, red inside the material.
            const glm::vec3 tint = tool.contact == 0   ? glm::vec3(0.45f, 1.0f, 0.5f)
                                   : tool.contact == 1 ? glm::vec3(1.0f, 0.9f, 0.3f)
                                                       : glm::vec3(1.0f, 0.35f, 0.3f);
            const glm::mat4 toolM =
                glm::scale(glm::translate(glm::mat4(1.f), glm::vec3(tool.worldPos)),
                           glm::vec3(float(tool.radiusMm)));
            glUniformMatrix4fv(mImpl->worldFromObjectLoc, 1, GL_FALSE, glm::value_ptr(toolM));
            glUniform3fv(mImpl->tintLoc, 1, glm::value_ptr(tint));
            if (tool.selectBox) glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
            mImpl->sphere.draw();
            glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
            if (tool.shadow) {
                // A dark, flattened disc on the surface under the tool.
                const float r = float(tool.radiusMm) * 0.9f;
                const glm::mat4 shadowM =
                    glm::scale(glm::translate(glm::mat4(1.f), glm::vec3(tool.shadowPos)),
                               glm::vec3(r, r, 0.08f * r));
                glUniformMatrix4fv(mImpl->worldFromObjectLoc, 1, GL_FALSE, glm::value_ptr(shadowM));
                const glm::vec3 dark(0.25f, 0.25f, 0.3f);
                glUniform3fv(mImpl->tintLoc, 1, glm::value_ptr(dark));
                mImpl->sphere.draw();
            }
        }
        if (ui && ui->texture && ui->usedX1 > ui->usedX0 && ui->usedY1 > ui->usedY0) {
            // The UI over the scene, shifted by this eye's disparity; before the lens
            // correction, so it is pre-distorted like the scene.
            compositeUi(*ui, mImpl->uiShift[e]);
        }
        if (corrected) {
            // Resample this eye through the lens correction into its half of the window.
            glBindFramebuffer(GL_FRAMEBUFFER, 0);
            glViewport(x0 + (e == 0 ? 0 : w / 2), 0, w / 2, h);
            glDisable(GL_DEPTH_TEST);
            glUseProgram(mImpl->postProgram);
            glActiveTexture(GL_TEXTURE0);
            glBindTexture(GL_TEXTURE_2D, mImpl->eyeColor);
            glUniform1i(glGetUniformLocation(mImpl->postProgram, "eyeImage"), 0);
            glUniform2f(glGetUniformLocation(mImpl->postProgram, "k"), float(lens.k1),
                        float(lens.k2));
            glUniform2f(glGetUniformLocation(mImpl->postProgram, "scaleRB"), float(lens.redScale),
                        float(lens.blueScale));
            glUniform1f(glGetUniformLocation(mImpl->postProgram, "aspect"),
                        float(mImpl->eyeW) / float(std::max(1, mImpl->eyeH)));
            glBindVertexArray(mImpl->postVao);
            glDrawArrays(GL_TRIANGLES, 0, 3);
            glEnable(GL_DEPTH_TEST);
        }
    }
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    detail::checkGl("Viewer::draw");
    stats.cpuMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return stats;
}

FrameStats Viewer::drawEye(const glm::dmat4& worldFromObject, const ToolDraw& tool,
                           const EyeView& eye, unsigned colorTexture, int width, int height) {
    const auto t0 = std::chrono::steady_clock::now();
    FrameStats stats;
    Impl& m = *mImpl;
    if (!m.xrFbo) glGenFramebuffers(1, &m.xrFbo);
    glBindFramebuffer(GL_FRAMEBUFFER, m.xrFbo);
    const bool multisample = m.eyeSamples > 1;
    if (!multisample && (m.xrW != width || m.xrH != height || !m.xrDepth)) {
        if (m.xrDepth) glDeleteRenderbuffers(1, &m.xrDepth);
        glGenRenderbuffers(1, &m.xrDepth);
        glBindRenderbuffer(GL_RENDERBUFFER, m.xrDepth);
        glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
        m.xrW = width;
        m.xrH = height;
    }
    // Multisampled: the texture only takes the resolve, so it needs no depth.
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                              multisample ? 0 : m.xrDepth);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, colorTexture, 0);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw RenderError("headset eye framebuffer incomplete");
    if (multisample) {
        // A resolve needs the same format on both sides: the swapchain image's.
        GLint format = 0;
        glBindTexture(GL_TEXTURE_2D, colorTexture);
        glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_INTERNAL_FORMAT, &format);
        glBindTexture(GL_TEXTURE_2D, 0);
        if (!m.msFbo) {
            glGenFramebuffers(1, &m.msFbo);
            glGenRenderbuffers(1, &m.msColor);
            glGenRenderbuffers(1, &m.msDepth);
        }
        glBindFramebuffer(GL_FRAMEBUFFER, m.msFbo);
        if (m.msW != width || m.msH != height || m.msSamples != m.eyeSamples ||
            m.msFormat != format) {
            glBindRenderbuffer(GL_RENDERBUFFER, m.msColor);
            glRenderbufferStorageMultisample(GL_RENDERBUFFER, m.eyeSamples, GLenum(format), width,
                                             height);
            glBindRenderbuffer(GL_RENDERBUFFER, m.msDepth);
            glRenderbufferStorageMultisample(GL_RENDERBUFFER, m.eyeSamples, GL_DEPTH_COMPONENT24,
                                             width, height);
            glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                                      m.msColor);
            glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                                      m.msDepth);
            m.msW = width;
            m.msH = height;
            m.msSamples = m.eyeSamples;
            m.msFormat = format;
        }
        if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
            throw RenderError("headset eye multisample framebuffer incomplete");
    }
    glViewport(0, 0, width, height);
    glEnable(GL_DEPTH_TEST);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glClearColor(kBackground[0] / 255.f, kBackground[1] / 255.f, kBackground[2] / 255.f, 1.f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glUseProgram(m.program);
    const glm::mat4 clip(eye.clipFromView * eye.viewFromWorld);
    const glm::mat4 object(worldFromObject);
    glUniformMatrix4fv(m.clipLoc, 1, GL_FALSE, glm::value_ptr(clip));
    glUniform3f(m.eyeLoc, float(eye.worldPosition.x), float(eye.worldPosition.y),
                float(eye.worldPosition.z));
    glUniformMatrix4fv(m.worldFromObjectLoc, 1, GL_FALSE, glm::value_ptr(object));
    glUniform3f(m.tintLoc, 1.f, 1.f, 1.f);
    const detail::ViewPlanes view(clip * object);
    for (const auto& [k, g] : m.chunks) {
        if (m.culling && view.outside(g.lo, g.hi)) continue;
        g.draw();
        ++stats.chunksDrawn;
        stats.triangles += size_t(g.count / 3);
    }
    if (m.lineMesh.count > 0) {
        glUniform3f(m.tintLoc, 0.75f, 0.12f, 0.1f);
        drawLinesOnSurface(m.lineMesh);
    }
    if (tool.visible) {
        // The same contact colours as the window: green air, yellow touching, red inside.
        const glm::vec3 tint = tool.contact == 0   ? glm::vec3(0.45f, 1.0f, 0.5f)
                               : tool.contact == 1 ? glm::vec3(1.0f, 0.9f, 0.3f)
                                                   : glm::vec3(1.0f, 0.35f, 0.3f);
        const glm::mat4 toolM = glm::scale(glm::translate(glm::mat4(1.f), glm::vec3(tool.worldPos)),
                                           glm::vec3(float(tool.radiusMm)));
        glUniformMatrix4fv(m.worldFromObjectLoc, 1, GL_FALSE, glm::value_ptr(toolM));
        glUniform3fv(m.tintLoc, 1, glm::value_ptr(tint));
        if (tool.selectBox) glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
        m.sphere.draw();
        glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
        if (tool.shadow) {
            // The depth cue, as in the window: a dark flattened disc on the surface below.
            const float r = float(tool.radiusMm) * 0.9f;
            const glm::mat4 shadowM =
                glm::scale(glm::translate(glm::mat4(1.f), glm::vec3(tool.shadowPos)),
                           glm::vec3(r, r, 0.08f * r));
            glUniformMatrix4fv(m.worldFromObjectLoc, 1, GL_FALSE, glm::value_ptr(shadowM));
            glUniform3f(m.tintLoc, 0.25f, 0.25f, 0.3f);
            m.sphere.draw();
        }
    }
    if (tool.pointer) {
        // A thin bright line from the pen to where it points; its normals face this eye, so
        // the headlight shading leaves it evenly bright.
        core::Mesh ray;
        ray.positions = {tool.pointerFrom, tool.pointerTo};
        for (const core::Vec3& p : ray.positions) {
            const core::Vec3 toEye = eye.worldPosition - p;
            ray.normals.push_back(glm::length(toEye) > 0 ? glm::normalize(toEye)
                                                         : core::Vec3(0, 0, 1));
        }
        ray.indices = {0, 1};
        m.pointerMesh.upload(ray);
        glUniformMatrix4fv(m.worldFromObjectLoc, 1, GL_FALSE, glm::value_ptr(glm::mat4(1.f)));
        glUniform3f(m.tintLoc, 0.75f, 0.95f, 1.1f);
        drawWholeLines(m.pointerMesh);
    }
    if (multisample) {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, m.msFbo);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, m.xrFbo);
        glBlitFramebuffer(0, 0, width, height, 0, 0, width, height, GL_COLOR_BUFFER_BIT,
                          GL_NEAREST);
        glBindFramebuffer(GL_FRAMEBUFFER, m.xrFbo);
    }
    // The compositor reads the texture next: detach it so the framebuffer holds no image.
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, 0, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    detail::checkGl("Viewer::drawEye");
    stats.cpuMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return stats;
}

int Viewer::setEyeSamples(int samples) {
    GLint most = 1;
    glGetIntegerv(GL_MAX_SAMPLES, &most);
    mImpl->eyeSamples = std::clamp(samples, 1, std::max(1, int(most)));
    return mImpl->eyeSamples;
}

int Viewer::windowSamples() const {
    return mImpl->windowSamples;
}

int Viewer::eyeSamples() const {
    return mImpl->eyeSamples;
}

void Viewer::setChunkCulling(bool on) {
    mImpl->culling = on;
}

void Viewer::blitToWindow(unsigned colorTexture, int width, int height) {
    Impl& m = *mImpl;
    if (!m.xrFbo) glGenFramebuffers(1, &m.xrFbo);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, m.xrFbo);
    glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, colorTexture,
                           0);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    const int w = this->width(), h = this->height();
    // Fit, keeping the eye's aspect.
    const double s = std::min(double(w) / std::max(1, width), double(h) / std::max(1, height));
    const int dw = int(width * s), dh = int(height * s), dx = (w - dw) / 2, dy = (h - dh) / 2;
    glClearColor(0.f, 0.f, 0.f, 1.f);
    glClear(GL_COLOR_BUFFER_BIT);
    glBlitFramebuffer(0, 0, width, height, dx, dy, dx + dw, dy + dh, GL_COLOR_BUFFER_BIT,
                      GL_LINEAR);
    glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, 0, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    detail::checkGl("Viewer::blitToWindow");
}

void Viewer::copyTexture(unsigned source, unsigned destination, int width, int height) {
    Impl& m = *mImpl;
    if (!m.copyFrom) {
        glGenFramebuffers(1, &m.copyFrom);
        glGenFramebuffers(1, &m.copyTo);
    }
    glBindFramebuffer(GL_READ_FRAMEBUFFER, m.copyFrom);
    glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, source, 0);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, m.copyTo);
    glFramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, destination,
                           0);
    glBlitFramebuffer(0, 0, width, height, 0, 0, width, height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glFramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, 0, 0);
    glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, 0, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    detail::checkGl("Viewer::copyTexture");
}

NativeGl Viewer::nativeGl() const {
    return detail::nativeGl(mImpl->window.get());
}

void Viewer::compositeUi(const UiImage& ui, double shiftNdc) {
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);  // the UI texture is premultiplied
    glUseProgram(mImpl->uiProgram);
    glBindVertexArray(mImpl->postVao);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, ui.texture);
    glUniform1i(glGetUniformLocation(mImpl->uiProgram, "ui"), 0);
    // Only the used part: the texture maps onto the whole eye image, shifted.
    const double w = std::max(1, ui.width), h = std::max(1, ui.height);
    const double u0 = ui.usedX0 / w, u1 = ui.usedX1 / w;
    const double v0 = 1 - ui.usedY1 / h, v1 = 1 - ui.usedY0 / h;
    glUniform4f(glGetUniformLocation(mImpl->uiProgram, "rect"), float(2 * u0 - 1 + shiftNdc),
                float(2 * v0 - 1), float(2 * u1 - 1 + shiftNdc), float(2 * v1 - 1));
    glUniform4f(glGetUniformLocation(mImpl->uiProgram, "uvRect"), float(u0), float(v0), float(u1),
                float(v1));
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
}

void Viewer::overlayUi(const UiImage& ui) {
    if (!ui.texture || ui.usedX1 <= ui.usedX0 || ui.usedY1 <= ui.usedY0) return;
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, width(), height());
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    compositeUi(ui, 0);
    detail::checkGl("Viewer::overlayUi");
}

glm::ivec2 Viewer::eyeImageSize(StereoMode mode) const {
    const int fullW = width(), h = height();
    const int x0 = mImpl->areaW > 0 ? std::min(mImpl->areaX, fullW - 1) : 0;
    const int w = mImpl->areaW > 0 ? std::max(1, std::min(mImpl->areaW, fullW - x0)) : fullW;
    return {std::max(1, mode == StereoMode::SideBySide ? w / 2 : w), std::max(1, h)};
}

glm::dvec2 Viewer::pointerOnUi(double x, double y, StereoMode mode, glm::ivec2 uiSize) const {
    int w = 0, h = 0;
    glfwGetWindowSize(mImpl->window.get(), &w, &h);
    windowToArea(x, w);
    double ex = x, ew = std::max(1, w), shift = 0;
    if (mode == StereoMode::SideBySide) {
        ew = std::max(1, w / 2);
        const int eye = ex >= ew ? 1 : 0;
        if (eye == 1) ex -= ew;
        shift = mImpl->uiShift[eye];
    }
    // Anaglyph: the eyes' shifts are opposite, the pointer is seen between them (no shift).
    const double nx = ex / ew * 2 - 1 - shift;
    return {(nx + 1) / 2 * uiSize.x, y / std::max(1, h) * uiSize.y};
}

glm::dvec2 Viewer::windowToFramebuffer(double x, double y) const {
    int w = 0, h = 0;
    glfwGetWindowSize(mImpl->window.get(), &w, &h);
    return {x * width() / std::max(1, w), y * height() / std::max(1, h)};
}

const StereoDisplay& Viewer::lastDisplay() const {
    return mImpl->lastDisplay;
}

double Viewer::lastUiShiftNdc(Eye eye) const {
    return mImpl->uiShift[int(eye)];
}

void Viewer::setSurfaceLines(const std::vector<std::vector<core::Vec3>>& lines) {
    if (lines == mImpl->lines) return;
    mImpl->lines = lines;
    core::Mesh m;
    for (const auto& line : lines) {
        for (size_t i = 0; i < line.size(); ++i) {
            if (i > 0) {
                m.indices.push_back(uint32_t(m.positions.size() - 1));
                m.indices.push_back(uint32_t(m.positions.size()));
            }
            m.positions.push_back(line[i]);
            // Lit as if facing the front camera, so the line reads as a dark-red ink line.
            m.normals.push_back(core::Vec3(0, -1, 0));
        }
    }
    if (m.indices.empty()) {
        mImpl->lineMesh.release();
        return;
    }
    mImpl->lineMesh.upload(m);
}

const EyeView& Viewer::monoEye() const {
    return mImpl->monoEye;
}

void Viewer::setViewArea(int x, int width) {
    mImpl->areaX = std::max(0, x);
    mImpl->areaW = std::max(0, width);
}

void Viewer::windowToArea(double& x, int& w) const {
    int ww = 0, wh = 0;
    glfwGetWindowSize(mImpl->window.get(), &ww, &wh);
    w = ww;
    if (mImpl->areaW <= 0) return;
    // Window coordinates may differ from framebuffer pixels (HiDPI): scale the area.
    const double toWindow = double(ww) / std::max(1, width());
    x -= mImpl->areaX * toWindow;
    w = std::max(1, int(std::lround(mImpl->areaW * toWindow)));
}

void Viewer::setTrackedHead(const std::optional<glm::dmat4>& worldFromHead) {
    mImpl->trackedHead = worldFromHead;
}

void Viewer::pixelToEyeNdc(double x, double y, StereoMode mode, double& nx, double& ny) const {
    int w = 0, h = 0;
    glfwGetWindowSize(mImpl->window.get(), &w, &h);
    windowToArea(x, w);
    double ex = x, ew = std::max(1, w);
    if (mode == StereoMode::SideBySide) {
        ew = std::max(1, w / 2);
        if (ex >= ew) ex -= ew;
    }
    nx = (ex + 0.5) / ew * 2 - 1;
    ny = 1 - (y + 0.5) / std::max(1, h) * 2;
}

bool Viewer::goFullscreen(int index) {
    int count = 0;
    GLFWmonitor** monitors = glfwGetMonitors(&count);
    if (index < 0 || index >= count) return false;
    const GLFWvidmode* mode = glfwGetVideoMode(monitors[index]);
    glfwSetWindowMonitor(mImpl->window.get(), monitors[index], 0, 0, mode->width, mode->height,
                         mode->refreshRate);
    return true;
}

void Viewer::makeCurrent() {
    glfwMakeContextCurrent(mImpl->window.get());
}

void Viewer::swap() {
    glfwSwapBuffers(mImpl->window.get());
}

Image Viewer::readFrame() {
    Image img;
    img.width = width();
    img.height = height();
    img.rgba.resize(size_t(img.width) * img.height * 4);
    std::vector<uint8_t> rows(img.rgba.size());
    glFinish();
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    if (mImpl->windowSamples > 1) {
        // Resolved by a blit into a single-sampled buffer: reading a multisampled window's
        // pixels directly is not a resolve everywhere (Mesa's llvmpipe under Xvfb returns
        // one sample's picture).
        GLuint fbo = 0, color = 0;
        glGenFramebuffers(1, &fbo);
        glGenRenderbuffers(1, &color);
        glBindRenderbuffer(GL_RENDERBUFFER, color);
        glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, img.width, img.height);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo);
        glFramebufferRenderbuffer(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                                  color);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
        glReadBuffer(GL_BACK);
        glBlitFramebuffer(0, 0, img.width, img.height, 0, 0, img.width, img.height,
                          GL_COLOR_BUFFER_BIT, GL_NEAREST);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
        glReadPixels(0, 0, img.width, img.height, GL_RGBA, GL_UNSIGNED_BYTE, rows.data());
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        glDeleteRenderbuffers(1, &color);
        glDeleteFramebuffers(1, &fbo);
    } else {
        glReadBuffer(GL_BACK);
        glReadPixels(0, 0, img.width, img.height, GL_RGBA, GL_UNSIGNED_BYTE, rows.data());
    }
    for (int y = 0; y < img.height; ++y)
        std::copy_n(rows.data() + size_t(img.height - 1 - y) * img.width * 4, size_t(img.width) * 4,
                    img.rgba.data() + size_t(y) * img.width * 4);
    return img;
}

void Viewer::pixelRay(double x, double y, core::Vec3& origin, core::Vec3& dir) const {
    int w = 0, h = 0;
    glfwGetWindowSize(mImpl->window.get(), &w, &h);
    windowToArea(x, w);
    const glm::dmat4 worldFromClip =
        glm::inverse(mImpl->monoEye.clipFromView * mImpl->monoEye.viewFromWorld);
    const double nx = (x + 0.5) / std::max(1, w) * 2 - 1, ny = 1 - (y + 0.5) / std::max(1, h) * 2;
    const glm::dvec4 pn = worldFromClip * glm::dvec4(nx, ny, -1, 1);
    const glm::dvec4 pf = worldFromClip * glm::dvec4(nx, ny, 1, 1);
    origin = core::Vec3(pn) / pn.w;
    dir = glm::normalize(core::Vec3(pf) / pf.w - origin);
}

std::string Viewer::rendererName() const {
    const auto* r = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    const auto* v = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    return std::string(r ? r : "?") + " / " + (v ? v : "?");
}

void Viewer::finish() {
    glFinish();
}

}  // namespace vsculpt::render
