// SPDX-License-Identifier: MIT
#include "vsculpt/render/SketchInk.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace vsculpt::render {

namespace {

bool finite(glm::dvec2 v) {
    return std::isfinite(v.x) && std::isfinite(v.y);
}

/// Per-point or whole-stroke values: checks the size and returns an accessor.
template <class T>
void checkPerPoint(const std::vector<T>& values, size_t points, const char* field) {
    if (values.size() != 1 && values.size() != points)
        throw std::invalid_argument(
            std::string("InkStroke.") + field + ": has " + std::to_string(values.size()) +
            " values; needs 1 or one per point (" + std::to_string(points) + ")");
}

struct Sample {
    glm::dvec2 v;  // view mm
    double h;      // half-width, view mm
    float d;       // darkness
};

class Builder {
  public:
    Builder(std::vector<InkVertex>& out, double pxPerMm) : mOut(out), mPxPerMm(pxPerMm) {}

    void triangle(glm::dvec2 a, float da, glm::dvec2 b, float db, glm::dvec2 c, float dc) {
        mOut.push_back({a, da});
        mOut.push_back({b, db});
        mOut.push_back({c, dc});
    }

    /// A fan around `s` from angle `start` sweeping `sweep` radians (either sign).
    void arc(const Sample& s, double start, double sweep) {
        if (s.h <= 0) return;
        // Chords of about 3 pixels keep the rim smooth at any zoom without flooding the
        // vertex buffer for hairlines.
        const double perCircle =
            std::clamp(std::ceil(2 * std::numbers::pi * s.h * mPxPerMm / 3.0), 8.0, 96.0);
        // An even count puts a vertex on the arc's bisector, so a cap reaches exactly the
        // half-width past the end point.
        const int half =
            std::max(1, int(std::ceil(0.5 * std::abs(sweep) / (2 * std::numbers::pi) * perCircle)));
        const int n = 2 * half;
        glm::dvec2 prev = s.v + s.h * glm::dvec2(std::cos(start), std::sin(start));
        for (int k = 1; k <= n; ++k) {
            const double a = start + sweep * k / n;
            const glm::dvec2 next = s.v + s.h * glm::dvec2(std::cos(a), std::sin(a));
            triangle(s.v, s.d, prev, s.d, next, s.d);
            prev = next;
        }
    }

    void segment(const Sample& a, const Sample& b, glm::dvec2 normal) {
        const glm::dvec2 a0 = a.v + normal * a.h, a1 = a.v - normal * a.h;
        const glm::dvec2 b0 = b.v + normal * b.h, b1 = b.v - normal * b.h;
        triangle(a0, a.d, a1, a.d, b0, b.d);
        triangle(a1, a.d, b1, b.d, b0, b.d);
    }

    /// Fills the wedge on the outer side of the turn at `s` between the segments with unit
    /// directions u0 (arriving) and u1 (leaving).
    void join(const Sample& s, glm::dvec2 u0, glm::dvec2 u1) {
        const double cross = u0.x * u1.y - u0.y * u1.x, dot = glm::dot(u0, u1);
        const double turn = std::atan2(cross, dot);
        if (std::abs(turn) < 1e-9) return;
        const glm::dvec2 n0(-u0.y, u0.x);
        // A left turn opens a gap on the right (-normal) side and vice versa.
        const glm::dvec2 outer0 = turn > 0 ? -n0 : n0;
        arc(s, std::atan2(outer0.y, outer0.x), turn);
    }

  private:
    std::vector<InkVertex>& mOut;
    double mPxPerMm;
};

}  // namespace

CanvasView CanvasView::zoomedAbout(glm::dvec2 viewPoint, double factor) const {
    if (!std::isfinite(factor) || factor <= 0)
        throw std::invalid_argument("CanvasView::zoomedAbout: factor must be finite and > 0");
    if (!finite(viewPoint))
        throw std::invalid_argument("CanvasView::zoomedAbout: viewPoint is not finite");
    CanvasView v = *this;
    const glm::dvec2 fixed = canvasFromView(viewPoint);
    v.zoom = zoom * factor;
    v.panMm = fixed - viewPoint / v.zoom;
    return v;
}

void validateCanvasView(const CanvasView& v) {
    if (!std::isfinite(v.zoom) || v.zoom <= 0)
        throw std::invalid_argument("CanvasView.zoom must be finite and > 0");
    if (!finite(v.panMm)) throw std::invalid_argument("CanvasView.panMm is not finite");
    if (!finite(v.viewportMm) || v.viewportMm.x <= 0 || v.viewportMm.y <= 0)
        throw std::invalid_argument("CanvasView.viewportMm must be finite and > 0");
    if (v.viewportPx.x <= 0 || v.viewportPx.y <= 0)
        throw std::invalid_argument("CanvasView.viewportPx must be > 0");
}

glm::vec3 inkRgb(InkClass cls, float darkness) {
    glm::vec3 ink{0.06f, 0.06f, 0.08f};
    float strength = 1.0f;
    switch (cls) {
        case InkClass::Draft:
        case InkClass::Clean:
            break;
        case InkClass::Selected:
            ink = {0.10f, 0.35f, 0.90f};
            break;
        case InkClass::Pending:
            ink = {0.20f, 0.42f, 0.30f};
            break;
        case InkClass::Consumed:
            strength = 0.35f;
            break;
        case InkClass::Outline:
            ink = {0.62f, 0.08f, 0.08f};
            break;
        case InkClass::SurfaceLine:
            ink = {0.05f, 0.50f, 0.15f};
            break;
        case InkClass::Sweep:
            ink = {0.45f, 0.15f, 0.60f};
            break;
        case InkClass::Cut:
            ink = {0.90f, 0.45f, 0.05f};
            break;
    }
    const float t = std::clamp(darkness, 0.0f, 1.0f) * strength;
    return kPaperRgb + (ink - kPaperRgb) * t;
}

std::vector<InkVertex> tessellateInk(const InkStroke& stroke, const CanvasView& view) {
    validateCanvasView(view);
    std::vector<InkVertex> out;
    const size_t n = stroke.pointsMm.size();
    if (n == 0) return out;
    checkPerPoint(stroke.widthMm, n, "widthMm");
    checkPerPoint(stroke.darkness, n, "darkness");
    for (size_t i = 0; i < n; ++i)
        if (!finite(stroke.pointsMm[i]))
            throw std::invalid_argument("InkStroke.pointsMm[" + std::to_string(i) +
                                        "] is not finite");
    for (size_t i = 0; i < stroke.widthMm.size(); ++i)
        if (!std::isfinite(stroke.widthMm[i]) || stroke.widthMm[i] < 0)
            throw std::invalid_argument("InkStroke.widthMm[" + std::to_string(i) +
                                        "] must be finite and >= 0");
    for (size_t i = 0; i < stroke.darkness.size(); ++i)
        if (!(stroke.darkness[i] >= 0 && stroke.darkness[i] <= 1))
            throw std::invalid_argument("InkStroke.darkness[" + std::to_string(i) +
                                        "] must be in [0, 1]");

    // Samples in view mm; points closer than this are one point (a pen resting in place
    // reports the same position many times, and a zero-length segment has no direction).
    const double mergeMm = 1e-9 * std::max(1.0, view.zoom);
    std::vector<Sample> s;
    s.reserve(n);
    double maxH = 0;
    for (size_t i = 0; i < n; ++i) {
        const Sample si{view.viewFromCanvas(stroke.pointsMm[i]),
                        0.5 * stroke.widthMm[stroke.widthMm.size() == 1 ? 0 : i] * view.zoom,
                        stroke.darkness[stroke.darkness.size() == 1 ? 0 : i]};
        maxH = std::max(maxH, si.h);
        if (!s.empty() && glm::length(si.v - s.back().v) <= mergeMm) {
            s.back().h = std::max(s.back().h, si.h);
            s.back().d = std::max(s.back().d, si.d);
            continue;
        }
        s.push_back(si);
    }
    if (maxH <= 0) return out;
    bool closed = stroke.closed;
    if (closed && s.size() > 1 && glm::length(s.back().v - s.front().v) <= mergeMm) s.pop_back();
    if (s.size() < 3) closed = false;

    const glm::dvec2 ppm = view.pixelsPerMm();
    Builder b(out, std::min(ppm.x, ppm.y));
    if (s.size() == 1) {
        b.arc(s[0], 0, 2 * std::numbers::pi);
        return out;
    }
    const size_t segments = closed ? s.size() : s.size() - 1;
    std::vector<glm::dvec2> dir(segments);
    for (size_t i = 0; i < segments; ++i)
        dir[i] = glm::normalize(s[(i + 1) % s.size()].v - s[i].v);
    for (size_t i = 0; i < segments; ++i)
        b.segment(s[i], s[(i + 1) % s.size()], glm::dvec2(-dir[i].y, dir[i].x));
    for (size_t i = 1; i < segments; ++i)
        b.join(s[i], dir[i - 1], dir[i]);
    if (closed) {
        b.join(s[0], dir[segments - 1], dir[0]);
    } else {
        // Half discs: the start cap sweeps from +normal through -direction, the end cap from
        // -normal through +direction.
        const glm::dvec2 u0 = dir.front(), u1 = dir.back();
        b.arc(s.front(), std::atan2(u0.x, -u0.y), std::numbers::pi);
        b.arc(s.back(), std::atan2(-u1.x, u1.y), std::numbers::pi);
    }
    return out;
}

}  // namespace vsculpt::render
