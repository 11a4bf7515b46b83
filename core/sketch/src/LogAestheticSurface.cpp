#include "vsculpt/sketch/LogAestheticSurface.h"

#include "vsculpt/sketch/CurveCurvature.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace vsculpt::sketch {

namespace {

void checkBase(const IntrinsicCurve& c, const char* name) {
    const std::string what = std::string("laSurface: ") + name;
    if (!(c.length > 0.0) || !std::isfinite(c.length))
        throw std::invalid_argument(what + " length must be finite and > 0");
    if (c.curvature.size() < 2 || c.curvature.size() != c.torsion.size())
        throw std::invalid_argument(what +
                                    " needs at least 2 curvature samples and as many torsions");
    for (std::size_t i = 0; i < c.curvature.size(); ++i)
        if (!std::isfinite(c.curvature[i]) || !std::isfinite(c.torsion[i]))
            throw std::invalid_argument(what + " has a non-finite value at sample " +
                                        std::to_string(i));
}

// Catmull–Rom through equally spaced samples, v ∈ [0, 1]; linear ghosts at the ends.
double sampleAt(const std::vector<double>& f, double v) {
    const std::size_t n = f.size();
    const double x = std::clamp(v, 0.0, 1.0) * double(n - 1);
    const std::size_t k = std::min(std::size_t(x), n - 2);
    const double t = x - double(k);
    const double p1 = f[k], p2 = f[k + 1];
    if (n == 2) return p1 + t * (p2 - p1);
    const double p0 = k > 0 ? f[k - 1] : 2 * p1 - p2;
    const double p3 = k + 2 < n ? f[k + 2] : 2 * p2 - p1;
    return 0.5 * (2 * p1 + (p2 - p0) * t + (2 * p0 - 5 * p1 + 4 * p2 - p3) * t * t +
                  (3 * p1 - p0 - 3 * p2 + p3) * t * t * t);
}

}  // namespace

IntrinsicCurve intrinsicCurve(const SpaceCurveSamples& curve) {
    if (curve.arcLength.size() < 2)
        throw std::invalid_argument("intrinsicCurve: need at least 2 samples");
    return {curve.arcLength.back(), curve.curvature, curve.torsion};
}

IntrinsicCurve intrinsicCurve(const Polyline3& curve, int samples, int halfWindow) {
    const CurveDifferential d = curveDifferential(resampleByCount(curve, samples), halfWindow);
    return {d.arcLength.back(), d.curvature, d.torsion};
}

double laInterpolate(double a, double b, double w, double gamma, bool* usedFallback) {
    if (usedFallback) *usedFallback = false;
    if (a == b || w == 0.0) return a;
    if (w == 1.0) return b;
    if (!(a * b > 0.0)) {
        if (usedFallback) *usedFallback = true;
        return (1.0 - w) * a + w * b;
    }
    const double ra = 1.0 / std::abs(a), rb = 1.0 / std::abs(b);
    double r;
    if (gamma == 0.0) {
        r = std::exp((1.0 - w) * std::log(ra) + w * std::log(rb));
    } else {
        const double pa = std::pow(ra, gamma), pb = std::pow(rb, gamma);
        r = std::pow(pa + w * (pb - pa), 1.0 / gamma);
    }
    return std::copysign(1.0 / r, a);
}

LaSurface laSurface(const Polyline3& guide, const IntrinsicCurve& base1,
                    const IntrinsicCurve& base2, const LaSurfaceParams& params) {
    checkBase(base1, "base line 1");
    checkBase(base2, "base line 2");
    if (!std::isfinite(params.gammaCurvature) || !std::isfinite(params.gammaTorsion))
        throw std::invalid_argument("laSurface: gamma must be finite");
    if (params.uSamples < 2 || params.vSamples < 2)
        throw std::invalid_argument("laSurface: uSamples and vSamples must be >= 2");
    const CurveDifferential g = curveDifferential(guide, params.halfWindow);
    const double guideLength = g.arcLength.back();
    if (params.useReferenceNormal) {
        const glm::dvec3& r = params.referenceNormal;
        if (!std::isfinite(r.x) || !std::isfinite(r.y) || !std::isfinite(r.z) ||
            !(glm::length(r) > 0.0))
            throw std::invalid_argument("laSurface: reference normal must be finite and non-zero");
    } else {
        for (std::size_t i = 0; i < g.curvature.size(); ++i) {
            if (!(g.curvature[i] * guideLength > 1e-9))
                throw std::invalid_argument(
                    "laSurface: the guide line is straight near point " + std::to_string(i) +
                    ", so its Frenet normal is undefined; set a reference normal");
            if (i > 0 && glm::dot(g.normal[i], g.normal[i - 1]) < 0.0)
                throw std::invalid_argument("laSurface: the guide line inflects near point " +
                                            std::to_string(i) + "; set a reference normal");
        }
    }

    LaSurface out;
    const int nu = params.uSamples, nv = params.vSamples;
    const std::size_t baseSamples = std::max(base1.curvature.size(), base2.curvature.size());
    const int substeps = std::max(4, int(std::ceil(4.0 * double(baseSamples) / double(nv - 1))));
    std::size_t seg = 1;
    for (int i = 0; i < nu; ++i) {
        const double w = double(i) / double(nu - 1);
        // Guide point and frame at arc length w·L (linear between guide samples).
        const double s = w * guideLength;
        while (seg + 1 < g.arcLength.size() && g.arcLength[seg] < s)
            ++seg;
        const double f = std::clamp(
            (s - g.arcLength[seg - 1]) / (g.arcLength[seg] - g.arcLength[seg - 1]), 0.0, 1.0);
        const glm::dvec3 point = guide[seg - 1] + f * (guide[seg] - guide[seg - 1]);
        const glm::dvec3 t =
            glm::normalize(g.tangent[seg - 1] + f * (g.tangent[seg] - g.tangent[seg - 1]));
        glm::dvec3 n = params.useReferenceNormal
                           ? params.referenceNormal
                           : g.normal[seg - 1] + f * (g.normal[seg] - g.normal[seg - 1]);
        n -= glm::dot(n, t) * t;
        if (!(glm::length(n) >
              1e-9 * (params.useReferenceNormal ? glm::length(params.referenceNormal) : 1.0)))
            throw std::invalid_argument(
                "laSurface: reference normal is parallel to the guide "
                "line at u = " +
                std::to_string(w));
        n = glm::normalize(n);
        const glm::dvec3 b = glm::cross(t, n);
        out.guideTangent.push_back(t);
        out.guideNormal.push_back(n);
        out.guideBinormal.push_back(b);

        const double length = (1.0 - w) * base1.length + w * base2.length;
        auto kappa = [&](double arc) {
            const double v = arc / length;
            return laInterpolate(sampleAt(base1.curvature, v), sampleAt(base2.curvature, v), w,
                                 params.gammaCurvature);
        };
        auto tau = [&](double arc) {
            const double v = arc / length;
            return laInterpolate(sampleAt(base1.torsion, v), sampleAt(base2.torsion, v), w,
                                 params.gammaTorsion);
        };
        for (int j = 0; j < nv; ++j) {
            const double v = double(j) / double(nv - 1);
            bool fk = false, ft = false;
            laInterpolate(sampleAt(base1.curvature, v), sampleAt(base2.curvature, v), w,
                          params.gammaCurvature, &fk);
            laInterpolate(sampleAt(base1.torsion, v), sampleAt(base2.torsion, v), w,
                          params.gammaTorsion, &ft);
            out.fallbackSamples += (fk || ft) ? 1 : 0;
        }
        // Section tangent b_g, section normal n_g (paper: t_b(0) = b_g, n_b(0) = n_g).
        out.sections.push_back(integrateFrenet({point, b, n}, length, kappa, tau, nv, substeps));
        for (const glm::dvec3& p : out.sections.back().points)
            out.mesh.vertices.push_back(p);
    }
    for (int i = 0; i + 1 < nu; ++i)
        for (int j = 0; j + 1 < nv; ++j)
            out.mesh.faces.push_back(
                {i * nv + j, (i + 1) * nv + j, (i + 1) * nv + j + 1, i * nv + j + 1});
    return out;
}

}  // namespace vsculpt::sketch
