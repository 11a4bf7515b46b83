// SPDX-License-Identifier: MIT
#include "vsculpt/core/ImportMesh.h"

#include "VdbMesh.h"
#include "vsculpt/core/PlaceSolid.h"
#include "vsculpt/core/PlyHeaderProblem.h"
#include "vsculpt/core/Project.h"
#include "vsculpt/core/ToolLevels.h"

#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/VolumeToMesh.h>
#include <assimp/Importer.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <mutex>
#include <sstream>
#include <unordered_map>

namespace vsculpt::core {

namespace {

// Beyond these an import is almost certainly a mistake (a scan at full resolution, a unit
// off by 1000) and would take minutes and gigabytes before placeSolid refused it anyway.
constexpr size_t kMaxTriangles = 20'000'000;
constexpr uintmax_t kMaxFileBytes = uintmax_t(2) << 30;
constexpr double kMaxCoordinateMm = 1e6;  // the lattices' range (validateSolidMesh)

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

std::string list(const std::vector<std::string>& v) {
    std::string out;
    for (size_t i = 0; i < v.size(); ++i)
        out += (i == 0 ? "" : i + 1 == v.size() ? " or " : ", ") + v[i];
    return out;
}

std::string fmt(double v) {
    std::ostringstream s;
    s.precision(4);
    s << v;
    return s.str();
}

[[noreturn]] void fail(const std::string& name, const std::string& why) {
    throw ImportError(name + ": " + why);
}

/// The format's own frame: the one exportMesh writes it in (ExportMesh.h), so the defaults
/// make export -> import an identity.
UpAxis defaultUp(const std::string& ext) {
    return ext == ".glb" || ext == ".gltf" || ext == ".obj" ? UpAxis::Y : UpAxis::Z;
}
double defaultMmPerUnit(const std::string& ext) {
    return ext == ".glb" || ext == ".gltf" ? 1000.0 : 1.0;
}

/// The frame vsculpt wrote the file in, when it says so: exports with --up/--units name it in
/// the STL header, the OBJ's first comment or the PLY's comment ("centimetres, +Y up"), so
/// such a file comes back where it was without the options (found by QA: an STL in cm came
/// back ten times small).
struct FileFrame {
    std::optional<UpAxis> up;
    std::optional<double> mmPerUnit;
};
FileFrame vsculptFrame(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::string head(256, '\0');
    in.read(head.data(), std::streamsize(head.size()));
    head.resize(size_t(std::max<std::streamsize>(0, in.gcount())));
    FileFrame f;
    if (head.find("vsculpt") == std::string::npos) return f;
    for (const auto& [word, mm] : {std::pair<const char*, double>{"millimetres, +", 1.0},
                                   {"centimetres, +", 10.0},
                                   {" metres, +", 1000.0}}) {
        const size_t at = head.find(word);
        if (at == std::string::npos) continue;
        const size_t axis = at + std::strlen(word);
        if (axis + 4 > head.size() || head.compare(axis + 1, 3, " up") != 0) continue;
        if (head[axis] != 'Y' && head[axis] != 'Z') continue;
        f.mmPerUnit = mm;
        f.up = head[axis] == 'Y' ? UpAxis::Y : UpAxis::Z;
        break;
    }
    return f;
}

/// File frame -> object space (Z up, mm): undo the export's quarter turn (x, y, z) ->
/// (x, z, -y), then scale.
Vec3 objectFromFile(const Vec3& p, UpAxis up, double mmPerUnit) {
    const Vec3 turned = up == UpAxis::Y ? Vec3(p.x, -p.z, p.y) : p;
    return turned * mmPerUnit;
}

struct PositionKey {
    double x, y, z;
    bool operator==(const PositionKey&) const = default;
};
struct PositionHash {
    size_t operator()(const PositionKey& k) const {
        size_t h = 1469598103934665603ull;
        for (double v : {k.x, k.y, k.z}) {
            uint64_t bits;
            std::memcpy(&bits, &v, sizeof bits);
            h = (h ^ bits) * 1099511628211ull;
            h ^= h >> 29;
        }
        return h;
    }
};

/// One triangle's corners as a sorted triple (its vertex set) and whether its winding is the
/// sorted order's cyclic one.
std::pair<std::array<uint32_t, 3>, bool> canonical(uint32_t a, uint32_t b, uint32_t c) {
    // Rotate so the smallest index comes first; the winding is then (a, b, c) or (a, c, b).
    while (a > b || a > c) {
        const uint32_t t = a;
        a = b;
        b = c;
        c = t;
    }
    if (b < c) return {{a, b, c}, true};
    return {{a, c, b}, false};
}

uint64_t edgeKey(uint32_t a, uint32_t b) {
    return (uint64_t(std::min(a, b)) << 32) | std::max(a, b);
}

bool rayHitsTriangle(const Vec3& o, const Vec3& d, const Vec3& a, const Vec3& b, const Vec3& c) {
    // Möller–Trumbore, counting hits strictly in front of the origin.
    const Vec3 e1 = b - a, e2 = c - a, p = glm::cross(d, e2);
    const double det = glm::dot(e1, p);
    if (std::abs(det) < 1e-300) return false;
    const double inv = 1 / det;
    const Vec3 s = o - a;
    const double u = glm::dot(s, p) * inv;
    if (u < 0 || u > 1) return false;
    const Vec3 q = glm::cross(s, e1);
    const double v = glm::dot(d, q) * inv;
    if (v < 0 || u + v > 1) return false;
    return glm::dot(e2, q) * inv > 0;
}

/// Welds equal positions, drops degenerate and duplicate triangles.
Mesh weld(const Mesh& in, ImportReport& r) {
    Mesh out;
    std::unordered_map<PositionKey, uint32_t, PositionHash> ids;
    ids.reserve(in.positions.size());
    std::vector<uint32_t> remap(in.positions.size());
    for (size_t i = 0; i < in.positions.size(); ++i) {
        const Vec3& p = in.positions[i];
        // +0 and -0 are the same place.
        const PositionKey k{p.x + 0.0, p.y + 0.0, p.z + 0.0};
        const auto [it, added] = ids.try_emplace(k, uint32_t(out.positions.size()));
        if (added) out.positions.push_back(p);
        remap[i] = it->second;
    }
    // Triangles by vertex set: a repeat is dropped, a back-to-back pair cancels.
    struct Kept {
        std::array<uint32_t, 3> set;
        bool cyclic;
        bool alive;
    };
    std::vector<Kept> kept;
    kept.reserve(in.triangleCount());
    for (size_t t = 0; t < in.triangleCount(); ++t) {
        const uint32_t a = remap[in.indices[3 * t]], b = remap[in.indices[3 * t + 1]],
                       c = remap[in.indices[3 * t + 2]];
        if (a == b || b == c || a == c) {
            ++r.droppedDegenerate;
            continue;
        }
        const auto [set, cyclic] = canonical(a, b, c);
        kept.push_back({set, cyclic, true});
    }
    // Sorting by vertex set groups repeats without a map of every triangle.
    std::vector<size_t> order(kept.size());
    for (size_t i = 0; i < order.size(); ++i)
        order[i] = i;
    std::sort(order.begin(), order.end(),
              [&](size_t x, size_t y) { return kept[x].set < kept[y].set; });
    for (size_t i = 0; i < order.size();) {
        size_t j = i;
        int cyclic = 0, reversed = 0;
        while (j < order.size() && kept[order[j]].set == kept[order[i]].set) {
            (kept[order[j]].cyclic ? cyclic : reversed)++;
            ++j;
        }
        if (j - i > 1) {
            // Keep one of the winding given more often; equal counts cancel to nothing.
            const int keep = cyclic == reversed ? 0 : 1;
            const bool keepCyclic = cyclic > reversed;
            int left = keep;
            for (size_t k = i; k < j; ++k) {
                Kept& t = kept[order[k]];
                if (left > 0 && t.cyclic == keepCyclic) {
                    --left;
                    continue;
                }
                t.alive = false;
                ++r.droppedDuplicate;
            }
        }
        i = j;
    }
    for (const Kept& t : kept) {
        if (!t.alive) continue;
        if (t.cyclic)
            out.indices.insert(out.indices.end(), {t.set[0], t.set[1], t.set[2]});
        else
            out.indices.insert(out.indices.end(), {t.set[0], t.set[2], t.set[1]});
    }
    return out;
}

// Ray-triangle tests allowed for telling cavities from solids (about a second).
constexpr size_t kMaxNestingWork = 200'000'000;

struct Orientation {
    size_t openEdges = 0, nonManifoldEdges = 0, conflicts = 0, flipped = 0;
    size_t cavities = 0;  // pieces inside an odd number of others
    bool nestingSkipped = false;
    bool closed() const { return openEdges == 0 && nonManifoldEdges == 0 && conflicts == 0; }
};

/// Winds each piece (triangles joined through manifold edges) consistently, then, when the
/// whole mesh is closed, turns each piece outward: a piece inside an odd number of others
/// (a cavity) faces inward, the rest outward.
Orientation orient(Mesh& m) {
    Orientation o;
    const size_t n = m.triangleCount();
    // Half-edges sorted by their undirected edge: each edge's uses lie side by side, and
    // `neighbour[3t + e]` is the one other use of a two-triangle edge (none otherwise).
    struct HalfEdge {
        uint64_t key;
        uint32_t slot;  // 3 * triangle + corner
    };
    std::vector<HalfEdge> half(3 * n);
    for (uint32_t slot = 0; slot < 3 * n; ++slot) {
        const uint32_t t = slot / 3, e = slot % 3;
        half[slot] = {edgeKey(m.indices[3 * t + e], m.indices[3 * t + (e + 1) % 3]), slot};
    }
    std::sort(half.begin(), half.end(), [](const HalfEdge& x, const HalfEdge& y) {
        return x.key < y.key || (x.key == y.key && x.slot < y.slot);
    });
    constexpr uint32_t kNone = uint32_t(-1);
    std::vector<uint32_t> neighbour(3 * n, kNone);
    for (size_t i = 0; i < half.size();) {
        size_t j = i;
        while (j < half.size() && half[j].key == half[i].key)
            ++j;
        if (j - i == 1) ++o.openEdges;
        if (j - i > 2) ++o.nonManifoldEdges;
        if (j - i == 2) {
            neighbour[half[i].slot] = half[i + 1].slot;
            neighbour[half[i + 1].slot] = half[i].slot;
        }
        i = j;
    }
    std::vector<HalfEdge>().swap(half);
    // Whether a triangle, as given, runs the edge at `slot` from its smaller vertex up.
    auto forward = [&](uint32_t slot) {
        const uint32_t t = slot / 3, e = slot % 3;
        return m.indices[3 * t + e] < m.indices[3 * t + (e + 1) % 3];
    };
    std::vector<int> piece(n, -1);
    std::vector<char> flip(n, 0);
    int pieces = 0;
    std::vector<uint32_t> stack;
    for (uint32_t seed = 0; seed < n; ++seed) {
        if (piece[seed] >= 0) continue;
        piece[seed] = pieces;
        stack.push_back(seed);
        while (!stack.empty()) {
            const uint32_t t = stack.back();
            stack.pop_back();
            for (uint32_t e = 0; e < 3; ++e) {
                const uint32_t otherSlot = neighbour[3 * t + e];
                if (otherSlot == kNone) continue;
                const uint32_t u = otherSlot / 3;
                // Neighbours must run their shared edge in opposite directions.
                const bool selfForward = forward(3 * t + e) != bool(flip[t]);
                const bool wantFlip = forward(otherSlot) == selfForward;
                if (piece[u] < 0) {
                    piece[u] = pieces;
                    flip[u] = wantFlip;
                    stack.push_back(u);
                } else if (bool(flip[u]) != wantFlip) {
                    ++o.conflicts;  // a Möbius-like piece: no consistent winding exists
                }
            }
        }
        ++pieces;
    }
    o.conflicts /= 2;  // each conflicting edge is seen from both sides
    auto rewind = [&](uint32_t t) { std::swap(m.indices[3 * t + 1], m.indices[3 * t + 2]); };
    for (uint32_t t = 0; t < n; ++t)
        if (flip[t]) rewind(t);
    if (!o.closed()) {
        for (uint32_t t = 0; t < n; ++t)
            o.flipped += flip[t];
        return o;
    }

    // Closed: each piece's signed volume and box, then nesting by ray parity.
    std::vector<double> volume(pieces, 0);
    std::vector<Aabb> box(pieces);
    std::vector<uint32_t> firstTriangle(pieces, uint32_t(-1));
    for (uint32_t t = 0; t < n; ++t) {
        const Vec3& a = m.positions[m.indices[3 * t]];
        const Vec3& b = m.positions[m.indices[3 * t + 1]];
        const Vec3& c = m.positions[m.indices[3 * t + 2]];
        volume[piece[t]] += glm::dot(a, glm::cross(b, c)) / 6;
        box[piece[t]].expand(a);
        box[piece[t]].expand(b);
        box[piece[t]].expand(c);
        if (firstTriangle[piece[t]] == uint32_t(-1)) firstTriangle[piece[t]] = t;
    }
    auto contains = [](const Aabb& outer, const Aabb& inner) {
        for (int a = 0; a < 3; ++a)
            if (inner.min[a] < outer.min[a] || inner.max[a] > outer.max[a]) return false;
        return true;
    };
    std::vector<size_t> trianglesIn(pieces, 0);
    for (uint32_t t = 0; t < n; ++t)
        ++trianglesIn[piece[t]];
    // Only a piece inside another's box can be inside it. A scan with thousands of bubbles
    // inside its body would cost rays through the body per bubble: past this budget every
    // piece faces outward (bubbles then fill) and the caller says so.
    std::vector<std::pair<int, int>> candidates;
    size_t work = 0;
    // Box tests are pairwise too: a mesh of more than 10,000 closed pieces skips them.
    if (pieces > 10'000) work = kMaxNestingWork + 1;
    for (int p = 0; p < pieces && work <= kMaxNestingWork; ++p)
        for (int q = 0; q < pieces; ++q)
            if (q != p && contains(box[q], box[p])) {
                candidates.emplace_back(p, q);
                work += trianglesIn[q];
            }
    std::vector<int> depth(pieces, 0);
    if (work > kMaxNestingWork) {
        o.nestingSkipped = true;
        candidates.clear();
    }
    std::vector<std::vector<uint32_t>> trianglesOf(candidates.empty() ? 0 : pieces);
    for (uint32_t u = 0; u < n && !candidates.empty(); ++u)
        trianglesOf[piece[u]].push_back(u);
    // An irrational-looking direction so the ray misses edges and vertices of grid-aligned
    // meshes.
    const Vec3 dir = glm::normalize(Vec3(0.8213, 0.4137, 0.3927));
    for (const auto& [p, q] : candidates) {
        // From a point on piece p (its first triangle's centroid): only q's crossings count.
        const uint32_t t = firstTriangle[p];
        const Vec3 origin = (m.positions[m.indices[3 * t]] + m.positions[m.indices[3 * t + 1]] +
                             m.positions[m.indices[3 * t + 2]]) /
                            3.0;
        int hits = 0;
        for (uint32_t u : trianglesOf[q])
            hits += rayHitsTriangle(origin, dir, m.positions[m.indices[3 * u]],
                                    m.positions[m.indices[3 * u + 1]],
                                    m.positions[m.indices[3 * u + 2]]);
        depth[p] += hits % 2;
    }
    std::vector<char> flipPiece(pieces, 0);
    for (int p = 0; p < pieces; ++p) {
        // Inside an even number of pieces: a solid, outward; odd: a cavity, inward.
        const bool wantPositive = depth[p] % 2 == 0;
        flipPiece[p] = (volume[p] > 0) != wantPositive && volume[p] != 0;
        o.cavities += !wantPositive;
    }
    for (uint32_t t = 0; t < n; ++t) {
        if (flipPiece[piece[t]]) {
            rewind(t);
            flip[t] = !flip[t];
        }
        o.flipped += flip[t];
    }
    return o;
}

Mesh fromVdb(const std::vector<openvdb::Vec3s>& points, const std::vector<openvdb::Vec3I>& tris,
             const std::vector<openvdb::Vec4I>& quads) {
    Mesh out;
    out.positions.reserve(points.size());
    for (const openvdb::Vec3s& p : points)
        out.positions.emplace_back(p.x(), p.y(), p.z());
    for (const openvdb::Vec3I& t : tris)
        out.indices.insert(out.indices.end(), {t.x(), t.y(), t.z()});
    for (const openvdb::Vec4I& q : quads)
        out.indices.insert(out.indices.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
    return out;
}

/// Rebuilds an open or non-manifold mesh as a closed one by a morphological closing on
/// voxels: the surface thickened by `gapMm` (the unsigned distance's `gapMm` iso-surface,
/// closed by construction, holes narrower than about 2 gapMm sealed), filled (OpenVDB marks
/// every voxel the outside cannot reach as inside), then shrunk by `gapMm` again. Concave
/// creases come out rounded to about gapMm; where the outside leaks in through a wider hole
/// only a thin shell is left, which the shrinking removes (the caller refuses an empty result).
Mesh repairByClosing(const Mesh& m, double voxelMm, double gapMm) {
    initializeOpenVdb();
    const auto xform = openvdb::math::Transform::createLinearTransform(voxelMm);
    const auto [points, triangles] = toVdbMesh(m);
    const float band = float(gapMm / voxelMm + 2);
    const openvdb::FloatGrid::Ptr distance =
        openvdb::tools::meshToUnsignedDistanceField<openvdb::FloatGrid>(*xform, points, triangles,
                                                                        {}, band);
    std::vector<openvdb::Vec3s> shellPoints;
    std::vector<openvdb::Vec3I> shellTriangles;
    std::vector<openvdb::Vec4I> shellQuads;
    openvdb::tools::volumeToMesh(*distance, shellPoints, shellTriangles, shellQuads, gapMm, 0.0);
    if (shellPoints.empty()) return {};
    // The thickened shell's both sides are closed surfaces; as one level set its inside is
    // the shell plus every pocket the outside cannot reach, i.e. the dilated solid.
    std::vector<openvdb::Vec3I> shellAll = shellTriangles;
    for (const openvdb::Vec4I& q : shellQuads) {
        shellAll.emplace_back(q[0], q[1], q[2]);
        shellAll.emplace_back(q[0], q[2], q[3]);
    }
    const openvdb::FloatGrid::Ptr dilated = openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(
        *xform, shellPoints, shellAll, float(gapMm / voxelMm + 3));
    std::vector<openvdb::Vec3s> outPoints;
    std::vector<openvdb::Vec3I> outTriangles;
    std::vector<openvdb::Vec4I> outQuads;
    openvdb::tools::volumeToMesh(*dilated, outPoints, outTriangles, outQuads, -gapMm, 0.0);
    Mesh out = fromVdb(outPoints, outTriangles, outQuads);
    // Whatever way round OpenVDB winds its faces, the solid's volume says which is out.
    if (meshVolume(out) < 0)
        for (size_t t = 0; t < out.triangleCount(); ++t)
            std::swap(out.indices[3 * t + 1], out.indices[3 * t + 2]);
    return out;
}

double surfaceArea(const Mesh& m) {
    double a = 0;
    for (size_t t = 0; t < m.triangleCount(); ++t) {
        const Vec3& p = m.positions[m.indices[3 * t]];
        a += 0.5 * glm::length(glm::cross(m.positions[m.indices[3 * t + 1]] - p,
                                          m.positions[m.indices[3 * t + 2]] - p));
    }
    return a;
}

}  // namespace

const std::vector<std::string>& importExtensions() {
    static const std::vector<std::string> v{".obj", ".stl", ".ply", ".gltf", ".glb"};
    return v;
}

double parseImportUnit(std::string_view text) {
    const std::string t = lower(std::string(text));
    if (t == "mm") return 1;
    if (t == "cm") return 10;
    if (t == "m") return 1000;
    if (t == "in") return 25.4;
    double v = 0;
    const auto [p, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (ec == std::errc() && p == text.data() + text.size() && std::isfinite(v) && v > 0 &&
        v <= 1e6)
        return v;
    if (ec == std::errc() && p == text.data() + text.size())  // a number, out of range
        throw std::invalid_argument("unit '" + std::string(text) +
                                    "' is out of range: give more than 0 to 1e6 mm per unit");
    throw std::invalid_argument("unknown unit '" + std::string(text) +
                                "' (use mm, cm, m, in or a number of mm per unit)");
}

Mesh makeSolidMesh(const Mesh& mesh, const std::string& name, const ImportOptions& options,
                   ImportReport* report) {
    ImportReport local;
    ImportReport& r = report ? *report : local;
    if (!(options.repairVoxelMm >= 0) || !std::isfinite(options.repairVoxelMm) ||
        !(options.repairGapMm >= 0) || !std::isfinite(options.repairGapMm))
        throw std::invalid_argument(name + ": repair voxel and gap must be sizes in mm");
    Mesh m = weld(mesh, r);
    r.vertices = m.positions.size();
    if (m.indices.empty())
        fail(name, "no triangles left after dropping " + std::to_string(r.droppedDegenerate) +
                       " degenerate and " + std::to_string(r.droppedDuplicate) +
                       " duplicate one(s): not a solid");
    const Orientation o = orient(m);
    r.openEdges = o.openEdges;
    r.nonManifoldEdges = o.nonManifoldEdges;
    r.flippedTriangles = o.flipped;
    if (o.flipped > 0)
        r.notes.push_back(name + ": " + std::to_string(o.flipped) +
                          " triangle(s) rewound to face outward");
    if (o.cavities > 0)
        // Placement fills what the outside cannot reach (PlaceSolid.h): clay has no hidden
        // voids. Said, so a hollow part's weight or a print's wall is not taken on trust.
        r.notes.push_back(name + ": " + std::to_string(o.cavities) + " enclosed cavit" +
                          (o.cavities == 1 ? "y" : "ies") +
                          " (a hollow inside the mesh) will be filled: clay is solid inside");
    if (o.nestingSkipped)
        r.notes.push_back(name +
                          ": too many pieces inside others to tell cavities "
                          "from solids; every piece faces outward (cavities are filled)");
    const bool inverted = o.closed() && !(meshVolume(m) > 0);
    if (!o.closed() || inverted) {
        std::string what = std::to_string(o.openEdges) + " open edge(s), " +
                           std::to_string(o.nonManifoldEdges) + " non-manifold edge(s)";
        if (o.conflicts > 0)
            what += ", " + std::to_string(o.conflicts) + " edge(s) with no consistent winding";
        if (inverted) what = "encloses no volume";
        if (!options.repair)
            fail(name, "not a closed surface (" + what +
                           "); import with repair on to rebuild it through a level set, or "
                           "close it in a mesh editor");
        const Aabb b = meshBounds(m);
        const Vec3 size = b.max - b.min;
        const double extent = std::max({size.x, size.y, size.z});
        if (!(extent > 0)) fail(name, "the mesh is flat or a point: nothing to enclose");
        const double wantGap = options.repairGapMm > 0 ? options.repairGapMm : extent / 32;
        // Four voxels across the gap keep the narrow bands (and the time) small; extent/128
        // is finer than any lattice the solid is placed on at its default level.
        const double voxel =
            options.repairVoxelMm > 0 ? options.repairVoxelMm : std::max(extent / 128, wantGap / 4);
        if (extent / voxel > 2048)
            throw std::invalid_argument(name + ": repair voxel " + fmt(voxel) +
                                        " mm is finer than 1/2048 of the mesh's extent " +
                                        fmt(extent) + " mm");
        // At least two voxels, so the thickened shell has an inside to mesh.
        const double gap = std::max(2 * voxel, wantGap);
        const double area = surfaceArea(m);
        m = repairByClosing(m, voxel, gap);
        r.repaired = true;
        r.repairVoxelMm = voxel;
        r.repairGapMm = gap;
        const MeshTopology topo = analyzeTopology(m);
        // A leak leaves at most slivers of the shell, about a voxel thick.
        if (m.indices.empty() || !(meshVolume(m) > area * voxel))
            fail(name, "not a closed surface (" + what +
                           ") and the repair found nothing enclosed: a hole is wider than "
                           "twice the repair gap (" +
                           fmt(gap) +
                           " mm); close it in a mesh editor or import with a larger "
                           "gap");
        if (!topo.watertight())
            fail(name, "not a closed surface (" + what + ") and the repair left " +
                           std::to_string(topo.boundaryEdges) + " open and " +
                           std::to_string(topo.nonManifoldEdges) +
                           " non-manifold edge(s); close it in a mesh editor");
        r.notes.push_back(name + ": not a closed surface (" + what +
                          "); rebuilt closed through a level set (" + fmt(voxel) +
                          " mm voxels, holes up to about " + fmt(2 * gap) +
                          " mm sealed, creases rounded to " + fmt(gap) + " mm)");
    }
    // What validateSolidMesh checks, by what is known here: orient() found every edge shared
    // by two triangles wound oppositely (or the repair's topology check did), so positions and
    // volume are left (its hash map of directed edges costs seconds on million-triangle scans,
    // and placeSolid runs it again anyway).
    for (const Vec3& p : m.positions)
        if (!isUsablePoint(p))
            fail(name, "a position is not finite or lies beyond 1e6 mm (check the units)");
    if (!(meshVolume(m) > 0)) fail(name, "encloses no volume");
    r.triangles = m.triangleCount();
    return m;
}

void checkImportFile(const std::filesystem::path& path, const ImportOptions& options) {
    const std::string name = path.string();
    const std::string ext = lower(path.extension().string());
    const auto& known = importExtensions();
    if (std::find(known.begin(), known.end(), ext) == known.end())
        fail(name, "cannot import '" + (ext.empty() ? std::string("(no extension)") : ext) +
                       "' files (supported: " + list(known) + ")");
    if (options.mmPerUnit && !(*options.mmPerUnit > 0 && std::isfinite(*options.mmPerUnit)))
        throw std::invalid_argument(name + ": units: mm per unit must be a positive number");
    if (options.fitMm && !(*options.fitMm > 0 && *options.fitMm <= kMaxCoordinateMm))
        throw std::invalid_argument(name + ": fit: the size must be positive and at most 1e6 mm");
    if (options.centreAt && !isUsablePoint(*options.centreAt))
        throw std::invalid_argument(name + ": centre: the point lies beyond 1e6 mm");

    // Assimp's own messages for a missing or unreadable file are vague; the OS's are not.
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) fail(name, "cannot read: it is a folder");
    {
        std::ifstream probe(path, std::ios::binary);
        if (!probe) {
            const int why = errno;
            fail(name, std::string("cannot read: ") + std::strerror(why));
        }
    }
    const uintmax_t bytes = std::filesystem::file_size(path, ec);
    if (!ec && bytes > kMaxFileBytes)
        fail(name, "too large to import (" + std::to_string(bytes >> 20) + " MiB; at most " +
                       std::to_string(kMaxFileBytes >> 20) + " MiB)");
    if (!ec && bytes == 0) fail(name, "empty file");
    if (ext == ".ply") {
        // Assimp hangs on a PLY header cut short and crashes on damaged ones: checked here,
        // on the header only (Assimp reads the whole file after).
        std::ifstream in(path, std::ios::binary);
        std::string start(kMaxPlyHeaderBytes, '\0');
        in.read(start.data(), std::streamsize(start.size()));
        start.resize(size_t(in.gcount()));
        if (const std::string problem = plyHeaderProblem(start, ec ? start.size() : bytes);
            !problem.empty())
            throw ImportError(name + ":" + problem);
    }
    if (ext == ".gltf" && !ec) {
        // Assimp says only "No suitable reader found" of a .gltf whose JSON is broken (found by
        // QA): name the line and column, as every other refusal of a file does.
        std::ifstream in(path, std::ios::binary);
        std::ostringstream text;
        text << in.rdbuf();
        const std::string json = text.str();
        try {
            const nlohmann::json parsed = nlohmann::json::parse(json);
            (void)parsed;  // only whether it parses, and where it does not
        } catch (const nlohmann::json::parse_error& e) {
            const size_t at = std::min<size_t>(e.byte > 0 ? e.byte - 1 : 0, json.size());
            const size_t line = size_t(std::count(json.begin(), json.begin() + long(at), '\n')) + 1;
            const size_t lineStart = json.rfind('\n', at == 0 ? 0 : at - 1);
            const size_t column = at - (lineStart == std::string::npos ? 0 : lineStart + 1) + 1;
            throw ImportError(name + ":" + std::to_string(line) + ":" + std::to_string(column) +
                              ": not valid glTF: its JSON does not parse");
        }
    }
    if (ext == ".stl" && !ec) {
        // Assimp says only "Failed to determine STL storage representation" of a binary STL
        // whose size disagrees with its triangle count (found by QA): say which way.
        std::ifstream in(path, std::ios::binary);
        std::string start(512, '\0');
        in.read(start.data(), std::streamsize(start.size()));
        start.resize(size_t(in.gcount()));
        // "solid" starts an ASCII STL (and some binary headers): Assimp tells those apart.
        const bool ascii = start.rfind("solid", 0) == 0;
        const bool text = std::all_of(
            start.begin(), start.begin() + std::min<size_t>(start.size(), 84),
            [](char c) { return std::isprint(uint8_t(c)) || std::isspace(uint8_t(c)); });
        if (!ascii && text) fail(name, "not an STL file: text that does not start with \"solid\"");
        if (!ascii) {
            if (bytes < 84)
                fail(name, "a binary STL needs an 84-byte header; the file has " +
                               std::to_string(bytes) + " bytes (truncated?)");
            const uint32_t count =
                uint32_t(uint8_t(start[80])) | uint32_t(uint8_t(start[81])) << 8 |
                uint32_t(uint8_t(start[82])) << 16 | uint32_t(uint8_t(start[83])) << 24;
            const uint64_t want = 84 + 50 * uint64_t(count);
            if (bytes != want)
                fail(name, "binary STL: its header says " + std::to_string(count) +
                               " triangle(s), " + std::to_string(want) +
                               " bytes, but the file has " + std::to_string(bytes) +
                               (bytes < want ? " (truncated: an interrupted copy or download?)"
                                             : " (bytes after the last triangle: damaged, or "
                                               "padded by the program that wrote it)"));
        }
    }
}

Mesh importMesh(const std::filesystem::path& path, const ImportOptions& options,
                ImportReport* report) {
    ImportReport local;
    ImportReport& r = report ? *report : local;
    const std::string name = path.string();
    const std::string ext = lower(path.extension().string());
    checkImportFile(path, options);

    Assimp::Importer importer;
    // Only positions and faces matter: everything else is dropped before the other steps.
    importer.SetPropertyInteger(
        AI_CONFIG_PP_RVC_FLAGS,
        aiComponent_NORMALS | aiComponent_TANGENTS_AND_BITANGENTS | aiComponent_COLORS |
            aiComponent_TEXCOORDS | aiComponent_BONEWEIGHTS | aiComponent_ANIMATIONS |
            aiComponent_TEXTURES | aiComponent_LIGHTS | aiComponent_CAMERAS);
    importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                                aiPrimitiveType_POINT | aiPrimitiveType_LINE);
    const aiScene* scene =
        importer.ReadFile(name, aiProcess_RemoveComponent | aiProcess_Triangulate |
                                    aiProcess_SortByPType | aiProcess_ValidateDataStructure);
    if (!scene) {
        std::string why = importer.GetErrorString();
        if (why.empty()) why = "unknown reason";
        fail(name, "not a mesh Assimp can read as " + ext + " (" + why + ")");
    }
    if (!scene->mRootNode || scene->mNumMeshes == 0) fail(name, "holds no triangle mesh");

    // Given options first, then what a vsculpt export says of itself, then the format's own.
    const FileFrame written =
        ext == ".stl" || ext == ".obj" || ext == ".ply" ? vsculptFrame(path) : FileFrame{};
    const UpAxis up = options.up.value_or(written.up.value_or(defaultUp(ext)));
    const double mmPerUnit =
        options.mmPerUnit.value_or(written.mmPerUnit.value_or(defaultMmPerUnit(ext)));

    // Flatten the node hierarchy: every mesh instance in the file's frame, merged.
    Mesh merged;
    size_t nonFinite = 0;
    struct Pending {
        const aiNode* node;
        aiMatrix4x4 parent;
    };
    std::vector<Pending> nodes{{scene->mRootNode, aiMatrix4x4()}};
    while (!nodes.empty()) {
        const Pending p = nodes.back();
        nodes.pop_back();
        const aiMatrix4x4 fileFromNode = p.parent * p.node->mTransformation;
        // A mirroring transform turns the winding inside out; put it back.
        const bool mirrored = fileFromNode.Determinant() < 0;
        for (unsigned i = 0; i < p.node->mNumMeshes; ++i) {
            const unsigned mi = p.node->mMeshes[i];
            if (mi >= scene->mNumMeshes) continue;
            const aiMesh* mesh = scene->mMeshes[mi];
            if (!(mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
            const uint32_t base = uint32_t(merged.positions.size());
            for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
                const aiVector3D q = fileFromNode * mesh->mVertices[v];
                const Vec3 filePoint(q.x, q.y, q.z);
                if (!std::isfinite(filePoint.x) || !std::isfinite(filePoint.y) ||
                    !std::isfinite(filePoint.z))
                    ++nonFinite;
                merged.positions.push_back(objectFromFile(filePoint, up, mmPerUnit));
            }
            for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
                const aiFace& face = mesh->mFaces[f];
                if (face.mNumIndices != 3) continue;
                if (merged.triangleCount() >= kMaxTriangles)
                    fail(name, "too large to import (more than " +
                                   std::to_string(kMaxTriangles / 1'000'000) +
                                   " million triangles); decimate it first");
                const uint32_t a = base + face.mIndices[0], b = base + face.mIndices[1],
                               c = base + face.mIndices[2];
                if (mirrored)
                    merged.indices.insert(merged.indices.end(), {a, c, b});
                else
                    merged.indices.insert(merged.indices.end(), {a, b, c});
            }
        }
        for (unsigned c = 0; c < p.node->mNumChildren; ++c)
            nodes.push_back({p.node->mChildren[c], fileFromNode});
    }
    r.fileTriangles = merged.triangleCount();
    if (nonFinite > 0)
        fail(name, std::to_string(nonFinite) + " vertex position(s) are not finite numbers");
    if (merged.indices.empty())
        fail(name, "holds no triangles (an empty mesh, or only points and lines)");

    // Options in the documented order: fit (about the origin), then centre.
    const Aabb box = meshBounds(merged);
    const Vec3 size = box.max - box.min;
    const double extent = std::max({size.x, size.y, size.z});
    double scale = 1;
    if (options.fitMm) {
        if (!(extent > 0)) fail(name, "fit: the mesh has no extent to scale");
        scale = *options.fitMm / extent;
    }
    Vec3 shift(0.0);
    if (options.centreAt) shift = *options.centreAt - (box.min + box.max) * 0.5 * scale;
    for (Vec3& p : merged.positions) {
        p = p * scale + shift;
        if (!isUsablePoint(p))
            fail(name, "reaches beyond 1e6 mm after turning and scaling (" + fmt(mmPerUnit) +
                           " mm per unit; check the units, or use fit)");
    }
    return makeSolidMesh(merged, name, options, &r);
}

int importLevelFor(const ToolLevels& levels, const Mesh& solid) {
    const double area = surfaceArea(solid), volume = meshVolume(solid);
    const double thickness = area > 0 ? volume / area : 0;
    const Aabb b = meshBounds(solid);
    auto vertices = [&](double h) {
        double n = 1;
        for (int a = 0; a < 3; ++a)
            n *= (b.max[a] - b.min[a]) / h + 4;
        return n;
    };
    // Coarse to fine: the first level fine enough, unless a finer one would not fit.
    int chosen = 0;
    std::vector<int> order;
    for (int k = 1; k <= 7; ++k)
        order.push_back(k);
    std::sort(order.begin(), order.end(),
              [&](int x, int y) { return levels.level(x).spacingMm > levels.level(y).spacingMm; });
    for (int k : order) {
        const double h = levels.level(k).spacingMm;
        // Every level finer than this one would hold too many vertices in one edit.
        if (volume / (h * h * h) > double(kMaxJournalSolidChanges) / 2 || vertices(h) > 3e7) break;
        chosen = k;
        if (h <= 0.5 * thickness) break;
    }
    return chosen ? chosen : order.front();
}

}  // namespace vsculpt::core
