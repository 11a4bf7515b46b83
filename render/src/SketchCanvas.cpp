// SPDX-License-Identifier: MIT
#include "vsculpt/render/SketchCanvas.h"

#include "GlCommon.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace vsculpt::render {

namespace {

const char* kInkVertex = R"(#version 330 core
layout(location = 0) in vec2 viewMm;
layout(location = 1) in vec3 rgb;
uniform vec2 viewportMm;
out vec3 vRgb;
void main() {
    vRgb = rgb;
    gl_Position = vec4(viewMm / viewportMm * 2.0 - 1.0, 0.0, 1.0);
})";

const char* kInkFragment = R"(#version 330 core
in vec3 vRgb;
out vec4 color;
void main() { color = vec4(vRgb, 1.0); })";

const char* kPaperVertex = R"(#version 330 core
void main() {
    // One triangle covering the viewport.
    vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
})";

// The grid is computed per pixel from the view, so it costs no geometry and never runs out:
// the canvas coordinate in units of the line spacing is view / (zoom * spacing) + phase, with
// the phase (fract(pan / spacing)) taken in double precision on the CPU so a far-panned
// canvas keeps sharp lines.
const char* kPaperFragment = R"(#version 330 core
uniform vec2 originPx;      // viewport's lower-left corner, window pixels
uniform vec2 pxPerSpacing;  // pixels between minor lines (x, y)
uniform vec2 phaseMinor;    // fract(pan / spacing)
uniform vec2 phaseMajor;    // fract(pan / (10 spacing))
uniform float minorFade;
uniform int grid;
uniform vec3 paper;
uniform vec3 lineColor;
out vec4 color;
float lines(vec2 px, vec2 pxPer, vec2 phase) {
    vec2 t = px / pxPer + phase;
    vec2 d = abs(fract(t + 0.5) - 0.5) * pxPer;  // pixels to the nearest line
    vec2 c = clamp(1.0 - d, 0.0, 1.0);
    return max(c.x, c.y);
}
void main() {
    vec3 c = paper;
    if (grid != 0) {
        vec2 px = gl_FragCoord.xy - originPx;
        float minor = lines(px, pxPerSpacing, phaseMinor) * minorFade;
        float major = lines(px, pxPerSpacing * 10.0, phaseMajor);
        c = mix(c, lineColor, max(0.30 * minor, 0.65 * major));
    }
    color = vec4(c, 1.0);
})";

constexpr double kMinGridViewMm = 5.0;

glm::dvec2 fractD(glm::dvec2 v) {
    return v - glm::floor(v);
}

void appendInk(std::vector<float>& data, const InkStroke& stroke, const CanvasView& view) {
    for (const InkVertex& v : tessellateInk(stroke, view)) {
        const glm::vec3 c = inkRgb(stroke.cls, v.darkness);
        data.insert(data.end(), {float(v.viewMm.x), float(v.viewMm.y), c.r, c.g, c.b});
    }
}

}  // namespace

double canvasGridSpacingMm(double zoom) {
    if (!std::isfinite(zoom) || zoom <= 0)
        throw std::invalid_argument("canvasGridSpacingMm: zoom must be finite and > 0");
    return std::pow(10.0, std::ceil(std::log10(kMinGridViewMm / zoom) - 1e-12));
}

struct SketchCanvas::Impl {
    GLuint inkProgram = 0, paperProgram = 0, vao = 0, vbo = 0;
    GLint viewportMmLoc = -1;
    GLint originLoc = -1, pxPerSpacingLoc = -1, phaseMinorLoc = -1, phaseMajorLoc = -1,
          fadeLoc = -1, gridLoc = -1, paperLoc = -1, lineLoc = -1;
    std::vector<float> data;
    ~Impl() {
        if (vbo) glDeleteBuffers(1, &vbo);
        if (vao) glDeleteVertexArrays(1, &vao);
        if (inkProgram) glDeleteProgram(inkProgram);
        if (paperProgram) glDeleteProgram(paperProgram);
    }
};

SketchCanvas::SketchCanvas() : mImpl(std::make_unique<Impl>()) {
    Impl& m = *mImpl;
    m.inkProgram = detail::linkProgram(kInkVertex, kInkFragment);
    m.paperProgram = detail::linkProgram(kPaperVertex, kPaperFragment);
    m.viewportMmLoc = glGetUniformLocation(m.inkProgram, "viewportMm");
    m.originLoc = glGetUniformLocation(m.paperProgram, "originPx");
    m.pxPerSpacingLoc = glGetUniformLocation(m.paperProgram, "pxPerSpacing");
    m.phaseMinorLoc = glGetUniformLocation(m.paperProgram, "phaseMinor");
    m.phaseMajorLoc = glGetUniformLocation(m.paperProgram, "phaseMajor");
    m.fadeLoc = glGetUniformLocation(m.paperProgram, "minorFade");
    m.gridLoc = glGetUniformLocation(m.paperProgram, "grid");
    m.paperLoc = glGetUniformLocation(m.paperProgram, "paper");
    m.lineLoc = glGetUniformLocation(m.paperProgram, "lineColor");
    glGenVertexArrays(1, &m.vao);
    glGenBuffers(1, &m.vbo);
    glBindVertexArray(m.vao);
    glBindBuffer(GL_ARRAY_BUFFER, m.vbo);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 5 * sizeof(float), nullptr);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 5 * sizeof(float),
                          reinterpret_cast<void*>(2 * sizeof(float)));
    glEnableVertexAttribArray(1);
    glBindVertexArray(0);
    detail::checkGl("SketchCanvas setup");
}

SketchCanvas::~SketchCanvas() = default;

CanvasStats SketchCanvas::draw(const std::vector<InkStroke>& ink, const CanvasView& view,
                               glm::ivec2 originPx, const CanvasOverlay& overlay) {
    validateCanvasView(view);
    Impl& m = *mImpl;
    CanvasStats stats;

    // Tessellate first: a bad stroke throws before any GL state changes.
    m.data.clear();
    const glm::dvec2 visMin = view.panMm, visMax = view.canvasFromView(view.viewportMm);
    for (const InkStroke& s : ink) {
        if (s.pointsMm.empty()) continue;
        glm::dvec2 lo(std::numeric_limits<double>::max()), hi(-lo);
        for (const glm::dvec2& p : s.pointsMm) {
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
        float wMax = 0;
        for (float w : s.widthMm)
            wMax = std::max(wMax, w);
        const double r = 0.5 * wMax + 1e-9;
        if (hi.x + r < visMin.x || lo.x - r > visMax.x || hi.y + r < visMin.y ||
            lo.y - r > visMax.y) {
            ++stats.strokesCulled;
            continue;
        }
        appendInk(m.data, s, view);
        ++stats.strokesDrawn;
    }
    const glm::dvec2 ppm = view.pixelsPerMm();
    const double canvasPerPx = 1.0 / (std::min(ppm.x, ppm.y) * view.zoom);
    if (!overlay.lassoMm.empty()) {
        InkStroke lasso{
            overlay.lassoMm, {float(1.5 * canvasPerPx)}, {1.0f}, InkClass::Selected, true};
        appendInk(m.data, lasso, view);
    }
    if (overlay.penMm) {
        if (!std::isfinite(overlay.penWidthMm) || overlay.penWidthMm < 0)
            throw std::invalid_argument("CanvasOverlay.penWidthMm must be finite and >= 0");
        // Never smaller than a few pixels, or the cursor vanishes for hairline pens.
        const double radius = std::max(0.5 * overlay.penWidthMm, 3 * canvasPerPx);
        if (overlay.penTouching) {
            appendInk(m.data,
                      {{*overlay.penMm}, {float(2 * radius)}, {0.6f}, InkClass::Draft, false},
                      view);
        }
        InkStroke ring{{}, {float(canvasPerPx)}, {0.8f}, InkClass::Draft, true};
        const int n = 48;
        for (int k = 0; k < n; ++k) {
            const double a = 2 * std::numbers::pi * k / n;
            ring.pointsMm.push_back(*overlay.penMm + radius * glm::dvec2(std::cos(a), std::sin(a)));
        }
        appendInk(m.data, ring, view);
    }
    stats.triangles = m.data.size() / 15;

    GLint oldViewport[4], oldScissor[4];
    glGetIntegerv(GL_VIEWPORT, oldViewport);
    glGetIntegerv(GL_SCISSOR_BOX, oldScissor);
    const GLboolean oldScissorOn = glIsEnabled(GL_SCISSOR_TEST),
                    oldDepthOn = glIsEnabled(GL_DEPTH_TEST), oldBlendOn = glIsEnabled(GL_BLEND);

    glViewport(originPx.x, originPx.y, view.viewportPx.x, view.viewportPx.y);
    glScissor(originPx.x, originPx.y, view.viewportPx.x, view.viewportPx.y);
    glEnable(GL_SCISSOR_TEST);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);

    // Paper and grid.
    const double spacing = canvasGridSpacingMm(view.zoom);
    const double viewSpacing = spacing * view.zoom;
    glUseProgram(m.paperProgram);
    glUniform2f(m.originLoc, float(originPx.x), float(originPx.y));
    glUniform2f(m.pxPerSpacingLoc, float(viewSpacing * ppm.x), float(viewSpacing * ppm.y));
    const glm::dvec2 phaseMinor = fractD(view.panMm / spacing),
                     phaseMajor = fractD(view.panMm / (10 * spacing));
    glUniform2f(m.phaseMinorLoc, float(phaseMinor.x), float(phaseMinor.y));
    glUniform2f(m.phaseMajorLoc, float(phaseMajor.x), float(phaseMajor.y));
    // Minor lines fade in as they spread apart, so zooming out does not pop a dense grid.
    glUniform1f(m.fadeLoc,
                float(std::clamp((viewSpacing - kMinGridViewMm) / (2 * kMinGridViewMm), 0.0, 1.0)));
    glUniform1i(m.gridLoc, overlay.grid ? 1 : 0);
    glUniform3f(m.paperLoc, kPaperRgb.r, kPaperRgb.g, kPaperRgb.b);
    glUniform3f(m.lineLoc, 0.55f, 0.65f, 0.80f);
    glBindVertexArray(m.vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);

    // Ink.
    if (!m.data.empty()) {
        glUseProgram(m.inkProgram);
        glUniform2f(m.viewportMmLoc, float(view.viewportMm.x), float(view.viewportMm.y));
        glBindBuffer(GL_ARRAY_BUFFER, m.vbo);
        glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(m.data.size() * sizeof(float)), m.data.data(),
                     GL_STREAM_DRAW);
        glDrawArrays(GL_TRIANGLES, 0, GLsizei(m.data.size() / 5));
    }
    glBindVertexArray(0);

    glViewport(oldViewport[0], oldViewport[1], oldViewport[2], oldViewport[3]);
    glScissor(oldScissor[0], oldScissor[1], oldScissor[2], oldScissor[3]);
    if (!oldScissorOn) glDisable(GL_SCISSOR_TEST);
    if (oldDepthOn) glEnable(GL_DEPTH_TEST);
    if (oldBlendOn) glEnable(GL_BLEND);
    detail::checkGl("SketchCanvas::draw");
    return stats;
}

}  // namespace vsculpt::render
