#include "vsculpt/sketch/SketchSolid.h"

#include "vsculpt/sketch/DooSabin.h"
#include "vsculpt/sketch/SelfIntersections.h"
#include "vsculpt/sketch/ThreeSection.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>

namespace vsculpt::sketch {
namespace {

[[noreturn]] void fail(const std::string& what) {
    throw std::invalid_argument("buildSketchSolid: " + what);
}

std::string pointText(const glm::dvec2& p) {
    std::ostringstream s;
    s.precision(4);
    s << "(" << p.x << ", " << p.y << ")";
    return s.str();
}

// The curve of a role, checked for presence, closedness and finite points.
const Polyline2& requireCurve(const std::optional<SketchCurve>& curve, const std::string& role,
                              bool closed) {
    if (!curve) fail(role + " missing");
    if (curve->closed != closed) fail(role + (closed ? " is not closed" : " must be open"));
    for (const glm::dvec2& p : curve->points)
        if (!std::isfinite(p.x) || !std::isfinite(p.y)) fail(role + " has a non-finite point");
    if (curve->points.size() < (closed ? 3u : 2u))
        fail(role + " needs at least " + (closed ? "3" : "2") + " points");
    return curve->points;
}

// Runs a step and prefixes its std::invalid_argument with the role it concerns.
template <typename Fn>
auto withRole(const std::string& role, Fn&& fn) {
    try {
        return fn();
    } catch (const std::invalid_argument& e) {
        fail(role + ": " + e.what());
    }
}

// Maps a mesh built in a view's canvas frame (x right, y up, z towards the viewer) to object
// space. right × up = towards the viewer for every view, so the map is a rotation and keeps the
// faces' orientation.
PolyMesh canvasMeshToObject(PolyMesh mesh, SketchPlane plane) {
    const SketchView v = sketchPlaneView(plane);
    const glm::dvec3 toward = glm::cross(v.right, v.up);
    for (glm::dvec3& p : mesh.vertices)
        p = p.x * v.right + p.y * v.up + p.z * toward;
    return mesh;
}

// The run of the closed outline (front view: canvas y = object z) at or below z = 0, from
// one crossing of z = 0 to the other, with the crossing points interpolated: curve (d).
Polyline2 lowerProfile(const Polyline2& outline) {
    const std::size_t n = outline.size();
    std::size_t start = n;
    for (std::size_t i = 0; i < n; ++i)
        if (outline[i].y > 0) {
            start = i;
            break;
        }
    if (start == n) fail("outline must reach above z = 0 (where surface line Y ends)");
    Polyline2 run;
    int runs = 0;
    bool below = false;
    for (std::size_t k = 1; k <= n; ++k) {
        const glm::dvec2 a = outline[(start + k - 1) % n], b = outline[(start + k) % n];
        const bool bBelow = b.y <= 0;
        if (bBelow != below) {
            // Crossing of z = 0 between a and b.
            const double t = a.y / (a.y - b.y);
            const glm::dvec2 c = a + t * (b - a);
            if (bBelow) {
                ++runs;
                run.push_back({c.x, 0.0});
            } else {
                if (run.empty() || run.back() != glm::dvec2(c.x, 0.0)) run.push_back({c.x, 0.0});
            }
            below = bBelow;
        }
        if (bBelow && (run.empty() || run.back() != b)) run.push_back(b);
    }
    if (runs == 0) fail("outline must reach below z = 0 (the lower profile)");
    if (runs > 1)
        fail("outline must cross z = 0 exactly twice (it crosses " + std::to_string(2 * runs) +
             " times)");
    return run;
}

PolyMesh buildInflate(const SketchSolidInput& in) {
    const Polyline2& outline = requireCurve(in.outline, "outline", true);
    return canvasMeshToObject(
        withRole("outline", [&] { return inflateOutline(outline, in.params.teddy); }),
        in.outlinePlane);
}

PolyMesh buildThreeSection(const SketchSolidInput& in) {
    const Polyline2& outline = requireCurve(in.outline, "outline", true);
    SurfaceLines lines;
    lines.back = requireCurve(in.surfaceLineY, "surface line Y", false);
    lines.belly = requireCurve(in.surfaceLineX, "surface line X", false);
    lines.torso = requireCurve(in.surfaceLineZ, "surface line Z", false);
    lines.bottom = lowerProfile(outline);
    // Orthographic views show the whole lower profile: nothing is hidden, so Eq. 1 must give
    // h4 = the outline's depth. With L1 = L2 = L3 = 1 it gives h4 = 2·h3.
    double depth = 0;
    for (const glm::dvec2& p : lines.bottom)
        depth = std::max(depth, -p.y);
    if (!(depth > 0)) fail("outline must reach below z = 0 (the lower profile)");
    lines.L1 = lines.L2 = lines.L3 = 1.0;
    lines.h3 = depth / 2;
    const ThreeSectionSolid solid = withRole("three-section lines", [&] {
        return reconstructThreeSections(lines, in.params.inverseChaikin);
    });
    if (in.params.threeSectionLevels < 0 || in.params.threeSectionLevels > 8)
        fail("params.threeSectionLevels must be in [0, 8]");
    return dooSabin(solid.controlMesh, in.params.threeSectionLevels);
}

PolyMesh requirePrevious(const SketchSolidInput& in) {
    if (!in.previous || in.previous->faces.empty()) fail("previous solid missing");
    if (!isClosedOriented(*in.previous))
        fail("previous solid is not closed and consistently oriented");
    return *in.previous;
}

PolyMesh buildCut(const SketchSolidInput& in) {
    const PolyMesh previous = requirePrevious(in);
    const Polyline2& stroke = requireCurve(in.cutStroke, "cut stroke", false);
    return withRole("cut stroke",
                    [&] { return cutMesh(previous, stroke, sketchPlaneView(in.cutPlane)); })
        .mesh;
}

PolyMesh buildExtrude(const SketchSolidInput& in) {
    const PolyMesh previous = requirePrevious(in);
    const Polyline2& base = requireCurve(in.extrudeBase, "extrude base stroke", true);
    const Polyline2& silhouette =
        requireCurve(in.extrudeSilhouette, "extrude silhouette stroke", false);
    return withRole("extrude",
                    [&] {
                        return extrudeMesh(previous, base, sketchPlaneView(in.extrudeBasePlane),
                                           silhouette, sketchPlaneView(in.extrudeSilhouettePlane),
                                           in.params.extrude);
                    })
        .mesh;
}

// ---- sweep ---------------------------------------------------------------------------------

[[noreturn]] void sweepFail(const std::string& what) {
    throw std::invalid_argument("sweepSectionAlongPath: " + what);
}

// Rotation taking unit a to unit b about a × b (Rodrigues), applied to v: the parallel
// transport of a frame vector between two consecutive segment directions.
glm::dvec3 transport(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& v) {
    const glm::dvec3 axis = glm::cross(a, b);
    const double s = glm::length(axis), c = glm::dot(a, b);
    if (s < 1e-15) return v;  // straight on (U-turns are rejected before this)
    const glm::dvec3 k = axis / s;
    return v * c + glm::cross(k, v) * s + k * glm::dot(k, v) * (1 - c);
}

struct SweepFrames {
    std::vector<glm::dvec3> tangent, side, up;  // per segment
};

SweepFrames frames(const Polyline3& p) {
    SweepFrames f;
    const std::size_t m = p.size() - 1;
    for (std::size_t j = 0; j < m; ++j)
        f.tangent.push_back(glm::normalize(p[j + 1] - p[j]));
    // Start with object z made perpendicular to the first segment (the top view's paths are
    // horizontal, so this is z itself); a vertical start falls back to y.
    glm::dvec3 up = glm::dvec3(0, 0, 1) - f.tangent[0] * f.tangent[0].z;
    if (glm::length(up) < 1e-6) up = glm::dvec3(0, 1, 0) - f.tangent[0] * f.tangent[0].y;
    up = glm::normalize(up);
    for (std::size_t j = 0; j < m; ++j) {
        if (j > 0) {
            up = transport(f.tangent[j - 1], f.tangent[j], up);
            up = glm::normalize(up - f.tangent[j] * glm::dot(up, f.tangent[j]));
        }
        f.up.push_back(up);
        f.side.push_back(glm::cross(up, f.tangent[j]));
    }
    return f;
}

// Ring i: the section in the frame of segment i − 1 (segment 0 for the first ring), moved
// along that segment onto the bisector plane of segments i − 1 and i.
std::vector<std::vector<glm::dvec3>> rings(const Polyline3& p, const SweepFrames& f,
                                           const Polyline2& offsets) {
    const std::size_t n = p.size(), m = n - 1;
    std::vector<std::vector<glm::dvec3>> out(n);
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t seg = i == 0 ? 0 : i - 1;
        const glm::dvec3 t = f.tangent[seg];
        const bool joint = i > 0 && i < m;
        const glm::dvec3 bisector = joint ? f.tangent[i - 1] + f.tangent[i] : t;
        for (const glm::dvec2& o : offsets) {
            const glm::dvec3 d = o.x * f.side[seg] + o.y * f.up[seg];
            out[i].push_back(p[i] + d - t * (glm::dot(d, bisector) / glm::dot(t, bisector)));
        }
    }
    return out;
}

// First segment whose two rings fold over each other (a ring point of the far end not ahead
// of the near end's along the segment), or m when none does.
std::size_t firstFold(const Polyline3& p, const SweepFrames& f,
                      const std::vector<std::vector<glm::dvec3>>& r) {
    for (std::size_t j = 0; j + 1 < p.size(); ++j) {
        const double len = glm::length(p[j + 1] - p[j]);
        for (std::size_t k = 0; k < r[j].size(); ++k)
            if (glm::dot(r[j + 1][k] - r[j][k], f.tangent[j]) < 0.05 * len) return j;
    }
    return p.size() - 1;
}

double turnAngle(const Polyline3& p, std::size_t i) {
    const glm::dvec3 a = glm::normalize(p[i] - p[i - 1]), b = glm::normalize(p[i + 1] - p[i]);
    return std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0));
}

Polyline2 preparePath(const Polyline2& path, double step) {
    // Merge points closer than step/2 (pen jitter), keeping both ends.
    Polyline2 kept{path.front()};
    for (std::size_t i = 1; i < path.size(); ++i)
        if (glm::length(path[i] - kept.back()) >= step / 2) kept.push_back(path[i]);
    if (glm::length(path.back() - kept.back()) > 0) {
        if (kept.size() > 1 && glm::length(path.back() - kept.back()) < step / 2)
            kept.back() = path.back();
        else
            kept.push_back(path.back());
    }
    // Split long segments so rings are about `step` apart.
    Polyline2 out{kept.front()};
    for (std::size_t i = 1; i < kept.size(); ++i) {
        const double len = glm::length(kept[i] - kept[i - 1]);
        const int pieces = std::max(1, int(std::ceil(len / step - 1e-9)));
        for (int k = 1; k <= pieces; ++k)
            out.push_back(kept[i - 1] + (kept[i] - kept[i - 1]) * (double(k) / pieces));
    }
    return out;
}

}  // namespace

const char* sketchPlaneName(SketchPlane plane) {
    return plane == SketchPlane::Front ? "front" : plane == SketchPlane::Side ? "side" : "top";
}

SketchView sketchPlaneView(SketchPlane plane) {
    SketchView v;
    switch (plane) {
        case SketchPlane::Front:
            v.right = {1, 0, 0};
            v.up = {0, 0, 1};
            break;
        case SketchPlane::Side:
            v.right = {0, 1, 0};
            v.up = {0, 0, 1};
            break;
        case SketchPlane::Top:
            v.right = {1, 0, 0};
            v.up = {0, 1, 0};
            break;
    }
    return v;
}

glm::dvec3 canvasToObject(SketchPlane plane, const glm::dvec2& canvas) {
    const SketchView v = sketchPlaneView(plane);
    return v.origin + canvas.x * v.right + canvas.y * v.up;
}

Polyline3 canvasToObject(SketchPlane plane, const Polyline2& canvas) {
    Polyline3 out;
    out.reserve(canvas.size());
    for (const glm::dvec2& p : canvas)
        out.push_back(canvasToObject(plane, p));
    return out;
}

const char* constructionName(SolidConstruction construction) {
    switch (construction) {
        case SolidConstruction::Inflate:
            return "inflate";
        case SolidConstruction::ThreeSection:
            return "three-section";
        case SolidConstruction::Sweep:
            return "sweep";
        case SolidConstruction::Cut:
            return "cut";
        case SolidConstruction::Extrude:
            return "extrude";
    }
    return "unknown";
}

PolyMesh sweepSectionAlongPath(const Polyline2& section, const Polyline2& path,
                               const SweepParams& params) {
    if (params.sectionSegments < 3) sweepFail("params.sectionSegments must be at least 3");
    if (!(params.step > 0) || !std::isfinite(params.step))
        sweepFail("params.step must be a positive number of mm");
    if (!(params.minPathLength > 0) || !std::isfinite(params.minPathLength))
        sweepFail("params.minPathLength must be a positive number of mm");
    if (params.subdivisionLevels < 0 || params.subdivisionLevels > 8)
        sweepFail("params.subdivisionLevels must be in [0, 8]");

    // Section: simple closed polygon, counter-clockwise, equal edges; offsets from its centroid.
    Polyline2 ring;
    try {
        ring = resampleOutline(section, params.sectionSegments);
    } catch (const std::invalid_argument& e) {
        sweepFail(std::string("sweep section: ") + e.what());
    }
    const glm::dvec2 centroid = areaCentroid(ring);
    Polyline2 offsets;
    double sectionRadius = 0;
    for (const glm::dvec2& q : ring) {
        offsets.push_back(q - centroid);
        sectionRadius = std::max(sectionRadius, glm::length(q - centroid));
    }

    // Path.
    for (const glm::dvec2& q : path)
        if (!std::isfinite(q.x) || !std::isfinite(q.y))
            sweepFail("sweep path has a non-finite point");
    Polyline2 distinct;
    for (const glm::dvec2& q : path)
        if (distinct.empty() || q != distinct.back()) distinct.push_back(q);
    if (distinct.size() < 2) sweepFail("sweep path needs at least 2 distinct points");
    const auto crossings = findSelfIntersections(distinct, false, 1);  // only the first is named
    if (!crossings.empty())
        sweepFail("sweep path crosses itself at " + pointText(crossings.front().point));
    const double pathLength = length(distinct, false);
    if (pathLength < params.minPathLength) {
        std::ostringstream s;
        s << "sweep path is too short: " << pathLength << " mm (at least " << params.minPathLength
          << " mm)";
        sweepFail(s.str());
    }
    const Polyline2 prepared = preparePath(distinct, params.step);
    Polyline3 p;
    std::vector<std::size_t> original;  // index in `prepared` of each point of p
    for (const glm::dvec2& q : prepared) {
        original.push_back(p.size());
        p.push_back({q.x, q.y, centroid.y});
    }

    // Drop points near sharp turns until no two consecutive rings fold over each other.
    SweepFrames f;
    std::vector<std::vector<glm::dvec3>> r;
    for (;;) {
        for (std::size_t i = 1; i + 1 < p.size(); ++i)
            if (turnAngle(p, i) > 0.75 * std::numbers::pi)
                sweepFail("sweep path turns back on itself at " + pointText({p[i].x, p[i].y}) +
                          " (a turn of more than 135°)");
        f = frames(p);
        r = rings(p, f, offsets);
        const std::size_t j = firstFold(p, f, r);
        if (j + 1 == p.size()) break;
        // Remove the straighter interior end of the folding segment.
        const bool aInterior = j > 0, bInterior = j + 1 < p.size() - 1;
        if (!aInterior && !bInterior)
            sweepFail("the section is too large for the sweep path's turns");  // 1 segment
        std::size_t drop;
        if (aInterior && bInterior)
            drop = turnAngle(p, j) <= turnAngle(p, j + 1) ? j : j + 1;
        else
            drop = aInterior ? j : j + 1;
        // Only points whose removal keeps the path within `step` of every prepared point it
        // replaces: a point on a straight run next to a corner, or on a rounded corner tighter
        // than the section. Anything else would silently straighten the user's path.
        const glm::dvec2 a = prepared[original[drop - 1]], b = prepared[original[drop + 1]];
        double deviation = 0;
        for (std::size_t o = original[drop - 1]; o <= original[drop + 1]; ++o) {
            const double t =
                std::clamp(glm::dot(prepared[o] - a, b - a) / glm::dot(b - a, b - a), 0.0, 1.0);
            deviation = std::max(deviation, glm::length(prepared[o] - (a + t * (b - a))));
        }
        if (deviation > params.step) {
            std::ostringstream s;
            s << "the section (" << sectionRadius << " mm from its centroid) is too large for "
              << "the sweep path's turn at " << pointText({p[drop].x, p[drop].y});
            sweepFail(s.str());
        }
        p.erase(p.begin() + std::ptrdiff_t(drop));
        original.erase(original.begin() + std::ptrdiff_t(drop));
    }

    // Walls: quads between consecutive rings; caps: the first and last rings.
    PolyMesh mesh;
    const int n = int(offsets.size()), rc = int(r.size());
    for (const auto& ringPoints : r)
        mesh.vertices.insert(mesh.vertices.end(), ringPoints.begin(), ringPoints.end());
    for (int i = 0; i + 1 < rc; ++i)
        for (int k = 0; k < n; ++k)
            mesh.faces.push_back(
                {i * n + k, i * n + (k + 1) % n, (i + 1) * n + (k + 1) % n, (i + 1) * n + k});
    std::vector<int> start, end;
    for (int k = n - 1; k >= 0; --k)
        start.push_back(k);
    for (int k = 0; k < n; ++k)
        end.push_back((rc - 1) * n + k);
    mesh.faces.push_back(start);
    mesh.faces.push_back(end);
    if (enclosedVolume(mesh) < 0)
        for (auto& face : mesh.faces)
            std::reverse(face.begin(), face.end());
    return params.subdivisionLevels > 0 ? dooSabin(mesh, params.subdivisionLevels) : mesh;
}

SketchSolid buildSketchSolid(const SketchSolidInput& in) {
    PolyMesh mesh;
    switch (in.construction) {
        case SolidConstruction::Inflate:
            mesh = buildInflate(in);
            break;
        case SolidConstruction::ThreeSection:
            mesh = buildThreeSection(in);
            break;
        case SolidConstruction::Sweep: {
            const Polyline2& section = requireCurve(in.sweepSection, "sweep section", true);
            const Polyline2& path = requireCurve(in.sweepPath, "sweep path", false);
            try {
                mesh = sweepSectionAlongPath(section, path, in.params.sweep);
            } catch (const std::invalid_argument& e) {
                fail(e.what());
            }
            break;
        }
        case SolidConstruction::Cut:
            mesh = buildCut(in);
            break;
        case SolidConstruction::Extrude:
            mesh = buildExtrude(in);
            break;
        default:
            fail("unknown construction");
    }

    SketchSolid out;
    const std::string name = constructionName(in.construction);
    if (!isClosedOriented(mesh))
        throw std::runtime_error("buildSketchSolid: the " + name +
                                 " result is not a closed, oriented solid");
    out.volume = enclosedVolume(mesh);
    if (!(out.volume > 0))
        throw std::runtime_error("buildSketchSolid: the " + name + " result has no volume");
    out.triangles = triangulatePolyMesh(mesh);
    const PolyMesh tri = toPolyMesh(out.triangles);
    if (!isClosedOriented(tri))
        throw std::runtime_error("buildSketchSolid: the " + name +
                                 " triangulation is not closed and oriented");
    // Volume centroid by the divergence theorem over the triangles (tetrahedra from the origin).
    glm::dvec3 moment(0.0);
    double volume6 = 0;
    for (const auto& t : tri.faces) {
        const glm::dvec3 a = tri.vertices[t[0]], b = tri.vertices[t[1]], c = tri.vertices[t[2]];
        const double v = glm::dot(a, glm::cross(b, c));
        volume6 += v;
        moment += v * (a + b + c);
    }
    out.centroid = moment / (4 * volume6);
    out.boundsMin = out.boundsMax = mesh.vertices.front();
    for (const glm::dvec3& v : mesh.vertices) {
        out.boundsMin = glm::min(out.boundsMin, v);
        out.boundsMax = glm::max(out.boundsMax, v);
    }
    out.polyMesh = std::move(mesh);
    return out;
}

}  // namespace vsculpt::sketch
