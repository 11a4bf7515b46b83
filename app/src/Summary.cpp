// SPDX-License-Identifier: MIT
#include "vsculpt/app/Summary.h"

#include "vsculpt/core/EvalField.h"
#include "vsculpt/core/Polygonizer.h"
#include "vsculpt/core/Sculpture.h"

#include <chrono>
#include <cstdio>
#include <ostream>
#include <string>

namespace vsculpt::app {

namespace {
template <typename... Args>
std::string fmt(const char* f, Args... args) {
    char buf[256];
    std::snprintf(buf, sizeof buf, f, args...);
    return buf;
}
}  // namespace

void printSummary(const core::Sculpture& s, std::ostream& out) {
    const core::SculptConfig& cfg = s.config();
    const core::ToolLevels& lv = s.levels();
    const core::FalloffParams& fp = cfg.falloff;
    out << "vsculpt 0.1.0: initial sculpture (headless summary)\n";
    out << "config: " << cfg.source << "\n";
    out << "placement mode: " << core::toString(cfg.placement) << "\n";
    out << fmt(
        "field: f = sum w F(d/R_k) - c, c = %.3g; F: f0 = %.3g, control point (u %.3g, "
        "F %.3g), slope %.3g\n",
        cfg.iso, fp.f0, fp.controlU, fp.controlValue, fp.controlSlope);
    out << "level  diameter_mm  spacing_mm  support_mm  L_k\n";
    for (int k = 1; k <= core::kLevelCount; ++k) {
        const core::ToolLevel& l = lv.level(k);
        out << fmt("%5d  %11.3f  %10.3f  %10.3f  %.4f\n", k, l.diameterMm, l.spacingMm, l.supportMm,
                   l.scale);
    }
    if (lv.calibrated()) {
        const core::CalibrationReport& r = lv.calibration();
        out << fmt(
            "support calibrated: R_k = %.6f D_k; straight-stroke tube radius vs D_k/2 over "
            "%d directions: mean error %.2e, worst direction %.2f%%, local ripple %.1f%%\n",
            r.supportOverDiameter, r.directions, r.meanRadiusError, 100 * r.worstDirectionError,
            100 * r.maxLocalDeviation);
    } else {
        out << "support radii set by hand (field.support), not calibrated\n";
    }
    const core::SkeletonCounts c = s.counts();
    out << "skeletons: " << c.total() << " (" << c.point << " point, " << c.lattice
        << " on lattices)\n";
    if (cfg.sphereRadiusMm > 0) {
        core::FieldProbe probe(s);
        const core::Vec3 center = cfg.sphereCenterMm;
        const core::Vec3 onSurface = center + core::Vec3(cfg.sphereRadiusMm, 0, 0);
        out << fmt(
            "initial sphere: radius %.3f mm at (%.3f, %.3f, %.3f); f(center) = %.4f, "
            "f(surface point) = %.2e, slope there %.4f per mm\n",
            cfg.sphereRadiusMm, center.x, center.y, center.z, probe.value(center),
            probe.value(onSurface), glm::length(probe.sample(onSurface).gradient));
        if (core::sphereCoreWeightIn(cfg) > 0)
            out << fmt("  steep core: weight %.3g, support %.3f mm (%.3g x the radius)\n",
                       cfg.sphereCoreWeight, cfg.sphereCoreSupportOverRadius * cfg.sphereRadiusMm,
                       cfg.sphereCoreSupportOverRadius);
        else if (cfg.placement == core::PlacementMode::Thesis)
            out << "  no steep core (thesis mode: the thesis's one point skeleton)\n";
        else
            out << "  no steep core (initial_sphere.core_weight 0: one point skeleton)\n";
    } else {
        out << "initial shape: empty space\n";
    }

    const core::GridRegion region = core::zoomRegion(cfg, lv, 1, cfg.sphereCenterMm);
    const auto t0 = std::chrono::steady_clock::now();
    core::Polygonizer poly(s, region, cfg.polygonizer.viewRootTolerance);
    const core::PolygonizeStats st = poly.rebuildAll();
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    const core::Mesh mesh = poly.mesh();
    const core::MeshTopology topo = core::analyzeTopology(mesh);
    out << fmt("zoom 1 grid: %d^3 cells of %.4f mm; tools offered:", region.n, region.spacingMm);
    for (int k : cfg.zoom.allowedSizes[0])
        out << " " << k;
    out << "\n";
    out << fmt(
        "mesh: %zu triangles, %zu vertices, %s, Euler characteristic %ld, %zu component(s), "
        "volume %.1f mm^3; polygonized in %.1f ms (%zu field evaluations)\n",
        mesh.triangleCount(), mesh.positions.size(),
        topo.watertight() ? "watertight" : "NOT watertight", topo.eulerCharacteristic,
        topo.components, core::meshVolume(mesh), ms, st.evaluations);
}

}  // namespace vsculpt::app
