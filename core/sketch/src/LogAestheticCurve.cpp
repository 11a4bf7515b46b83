#include "vsculpt/sketch/LogAestheticCurve.h"

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace vsculpt::sketch {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

void requireFinite(double v, const char* what, const char* name) {
    if (!std::isfinite(v))
        throw std::invalid_argument(std::string(what) + ": " + name + " is not finite");
}

// 8-point Gauss–Legendre rule on [−1, 1].
constexpr std::array<double, 4> kGaussX{0.1834346424956498, 0.5255324099163290, 0.7966664774136267,
                                        0.9602898564975363};
constexpr std::array<double, 4> kGaussW{0.3626837833783620, 0.3137066458778873, 0.2223810344533745,
                                        0.1012285362903763};

struct PlanarLaw {
    double alpha, lambda, k0, sign, theta0;
    double relKappa(double s) const { return laRelativeCurvature(alpha, lambda, s * k0); }
    double theta(double s) const { return theta0 + sign * laTurningAngle(alpha, lambda, s * k0); }
};

glm::dvec2 integrateChord(const PlanarLaw& law, double a, double b, int depth) {
    const double dTheta = std::abs(law.theta(b) - law.theta(a));
    const double ka = law.relKappa(a), kb = law.relKappa(b);
    const double ratio = ka > kb ? ka / kb : kb / ka;
    if ((dTheta > 0.1 || ratio > 1.5) && depth < 48) {
        const double m = 0.5 * (a + b);
        return integrateChord(law, a, m, depth + 1) + integrateChord(law, m, b, depth + 1);
    }
    const double half = 0.5 * (b - a), mid = 0.5 * (a + b);
    glm::dvec2 sum(0.0);
    for (std::size_t i = 0; i < kGaussX.size(); ++i) {
        for (double sgn : {-1.0, 1.0}) {
            const double t = law.theta(mid + sgn * half * kGaussX[i]);
            sum += kGaussW[i] * glm::dvec2(std::cos(t), std::sin(t));
        }
    }
    return half * sum;
}

glm::dmat3 rotation(const glm::dvec3& phi) {
    const double angle = glm::length(phi);
    glm::dmat3 k(0.0);
    k[0] = glm::dvec3(0.0, phi.z, -phi.y);
    k[1] = glm::dvec3(-phi.z, 0.0, phi.x);
    k[2] = glm::dvec3(phi.y, -phi.x, 0.0);
    double a, b;  // sin(φ)/φ and (1 − cos φ)/φ²
    if (angle < 1e-4) {
        const double a2 = angle * angle;
        a = 1.0 - a2 / 6.0 + a2 * a2 / 120.0;
        b = 0.5 - a2 / 24.0 + a2 * a2 / 720.0;
    } else {
        a = std::sin(angle) / angle;
        b = (1.0 - std::cos(angle)) / (angle * angle);
    }
    return glm::dmat3(1.0) + a * k + b * (k * k);
}

void orthonormalize(glm::dmat3& f) {
    f[0] = glm::normalize(f[0]);
    f[1] = glm::normalize(f[1] - glm::dot(f[1], f[0]) * f[0]);
    f[2] = glm::cross(f[0], f[1]);
}

}  // namespace

double laRelativeCurvature(double alpha, double lambda, double s) {
    if (alpha == 0.0) return std::exp(-lambda * s);
    const double x = lambda * alpha * s;
    if (!(x > -1.0)) return kInf;
    return std::exp(-std::log1p(x) / alpha);
}

double laTurningAngle(double alpha, double lambda, double s) {
    if (lambda == 0.0 || s == 0.0) return s;
    if (alpha == 0.0) return -std::expm1(-lambda * s) / lambda;
    const double x = lambda * alpha * s;
    if (!(x > -1.0)) return kInf;
    const double l = std::log1p(x);
    if (alpha == 1.0) return l / lambda;
    return std::expm1((alpha - 1.0) / alpha * l) / (lambda * (alpha - 1.0));
}

double laDomainLength(double alpha, double lambda) {
    return alpha * lambda < 0.0 ? -1.0 / (lambda * alpha) : kInf;
}

double laLambdaForRadiusRatio(double alpha, double radiusRatio, double normalizedLength) {
    if (!(radiusRatio > 0.0) || !std::isfinite(radiusRatio) || !(normalizedLength > 0.0) ||
        !std::isfinite(normalizedLength) || !std::isfinite(alpha))
        throw std::invalid_argument(
            "laLambdaForRadiusRatio: need finite alpha, radius ratio > 0 and length > 0");
    const double logRatio = std::log(radiusRatio);
    if (alpha == 0.0) return logRatio / normalizedLength;
    return std::expm1(alpha * logRatio) / (alpha * normalizedLength);
}

LaPlanarCurve laPlanarCurve(const LaPlanarParams& p, int samples) {
    const char* what = "laPlanarCurve";
    requireFinite(p.alpha, what, "alpha");
    requireFinite(p.lambda, what, "lambda");
    requireFinite(p.startCurvature, what, "startCurvature");
    requireFinite(p.length, what, "length");
    requireFinite(p.start.x, what, "start.x");
    requireFinite(p.start.y, what, "start.y");
    requireFinite(p.startAngle, what, "startAngle");
    if (p.startCurvature == 0.0)
        throw std::invalid_argument("laPlanarCurve: startCurvature must be non-zero");
    if (!(p.length > 0.0)) throw std::invalid_argument("laPlanarCurve: length must be > 0");
    if (samples < 2) throw std::invalid_argument("laPlanarCurve: need at least 2 samples");
    const double k0 = std::abs(p.startCurvature);
    if (!(p.length * k0 < laDomainLength(p.alpha, p.lambda)))
        throw std::invalid_argument(
            "laPlanarCurve: length passes the end of the curve (curvature becomes infinite at "
            "s = " +
            std::to_string(laDomainLength(p.alpha, p.lambda) / k0) + " mm)");

    const PlanarLaw law{p.alpha, p.lambda, k0, p.startCurvature > 0.0 ? 1.0 : -1.0, p.startAngle};
    LaPlanarCurve c;
    c.points.reserve(std::size_t(samples));
    glm::dvec2 pos = p.start;
    double prev = 0.0;
    for (int i = 0; i < samples; ++i) {
        const double s = i == samples - 1 ? p.length : p.length * double(i) / (samples - 1);
        if (i > 0) pos += integrateChord(law, prev, s, 0);
        prev = s;
        c.points.push_back(pos);
        c.arcLength.push_back(s);
        c.curvature.push_back(p.startCurvature * law.relKappa(s));
        c.tangentAngle.push_back(law.theta(s));
    }
    return c;
}

SpaceCurveSamples integrateFrenet(const FrenetStart& start, double length,
                                  const std::function<double(double)>& curvature,
                                  const std::function<double(double)>& torsion, int samples,
                                  int substeps) {
    const char* what = "integrateFrenet";
    for (int c = 0; c < 3; ++c) {
        requireFinite(start.point[c], what, "start point");
        requireFinite(start.tangent[c], what, "start tangent");
        requireFinite(start.normal[c], what, "start normal");
    }
    requireFinite(length, what, "length");
    if (!(length > 0.0)) throw std::invalid_argument("integrateFrenet: length must be > 0");
    if (samples < 2 || substeps < 1)
        throw std::invalid_argument("integrateFrenet: need samples >= 2 and substeps >= 1");
    const double tLen = glm::length(start.tangent);
    if (!(tLen > 0.0)) throw std::invalid_argument("integrateFrenet: start tangent is zero");
    const glm::dvec3 t0 = start.tangent / tLen;
    const glm::dvec3 nPerp = start.normal - glm::dot(start.normal, t0) * t0;
    if (!(glm::length(nPerp) > 1e-9 * glm::length(start.normal)) ||
        !(glm::length(start.normal) > 0.0))
        throw std::invalid_argument(
            "integrateFrenet: start normal is zero or parallel to the start tangent");
    glm::dmat3 f(t0, glm::normalize(nPerp), glm::dvec3(0.0));
    f[2] = glm::cross(f[0], f[1]);

    auto omega = [&](double s) {
        const double k = curvature(s), t = torsion(s);
        if (!std::isfinite(k) || !std::isfinite(t))
            throw std::invalid_argument("integrateFrenet: curvature or torsion not finite at s = " +
                                        std::to_string(s) + " mm");
        return glm::dvec3(t, 0.0, k);
    };
    const double g = std::sqrt(3.0) / 6.0;
    auto magnus = [&](double s, double h) {
        const glm::dvec3 w1 = omega(s + (0.5 - g) * h), w2 = omega(s + (0.5 + g) * h);
        return rotation(0.5 * h * (w1 + w2) + (std::sqrt(3.0) / 12.0) * h * h * glm::cross(w1, w2));
    };

    SpaceCurveSamples out;
    glm::dvec3 pos = start.point;
    auto record = [&](double s) {
        out.points.push_back(pos);
        out.arcLength.push_back(s);
        const glm::dvec3 w = omega(s);
        out.curvature.push_back(w.z);
        out.torsion.push_back(w.x);
        out.tangent.push_back(f[0]);
        out.normal.push_back(f[1]);
        out.binormal.push_back(f[2]);
    };
    record(0.0);
    const int steps = (samples - 1) * substeps;
    const double h = length / steps;
    for (int k = 0; k < steps; ++k) {
        const double s = h * k;
        const glm::dvec3 tMid = (f * magnus(s, 0.5 * h))[0];
        glm::dmat3 next = f * magnus(s, h);
        orthonormalize(next);
        pos += (h / 6.0) * (f[0] + 4.0 * tMid + next[0]);
        f = next;
        if ((k + 1) % substeps == 0) record(k + 1 == steps ? length : h * (k + 1));
    }
    return out;
}

SpaceCurveSamples laSpaceCurve(const LaSpaceParams& p, int samples, int substeps) {
    const char* what = "laSpaceCurve";
    requireFinite(p.alpha, what, "alpha");
    requireFinite(p.lambda, what, "lambda");
    requireFinite(p.startCurvature, what, "startCurvature");
    requireFinite(p.beta, what, "beta");
    requireFinite(p.omega, what, "omega");
    requireFinite(p.startTorsion, what, "startTorsion");
    requireFinite(p.length, what, "length");
    if (!(p.startCurvature > 0.0))
        throw std::invalid_argument("laSpaceCurve: startCurvature must be > 0");
    if (!(p.length > 0.0)) throw std::invalid_argument("laSpaceCurve: length must be > 0");
    const double k0 = p.startCurvature;
    const double t0 = std::abs(p.startTorsion);
    if (!(p.length * k0 < laDomainLength(p.alpha, p.lambda)))
        throw std::invalid_argument("laSpaceCurve: length passes the end of the curvature law");
    if (t0 > 0.0 && !(p.length * t0 < laDomainLength(p.beta, p.omega)))
        throw std::invalid_argument("laSpaceCurve: length passes the end of the torsion law");
    return integrateFrenet(
        p.start, p.length,
        [&](double s) { return k0 * laRelativeCurvature(p.alpha, p.lambda, s * k0); },
        [&](double s) {
            return t0 > 0.0 ? p.startTorsion * laRelativeCurvature(p.beta, p.omega, s * t0) : 0.0;
        },
        samples, substeps);
}

}  // namespace vsculpt::sketch
