#include "vsculpt/sketch/DooSabin.h"

#include <cmath>
#include <cstdint>
#include <numbers>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

namespace vsculpt::sketch {

namespace {

std::uint64_t key(int a, int b) {
    return (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b);
}

void checkInput(const PolyMesh& mesh) {
    if (mesh.faces.empty()) throw std::invalid_argument("dooSabin: the mesh has no faces");
    if (!isClosedOriented(mesh))
        throw std::invalid_argument(
            "dooSabin: the mesh must be closed and consistently oriented (every edge used once "
            "in each direction)");
    std::vector<char> used(mesh.vertices.size(), 0);
    for (const auto& face : mesh.faces)
        for (int v : face)
            used[v] = 1;
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
        if (!used[v])
            throw std::invalid_argument("dooSabin: vertex " + std::to_string(v) +
                                        " is used by no face");
        const auto& p = mesh.vertices[v];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            throw std::invalid_argument("dooSabin: vertex " + std::to_string(v) + " is not finite");
    }
}

PolyMesh step(const PolyMesh& mesh) {
    PolyMesh out;
    // corner[f][i]: new vertex made for corner i of face f.
    std::vector<std::vector<int>> corner(mesh.faces.size());
    // Directed edge a→b → (face, corner index of a in that face).
    std::unordered_map<std::uint64_t, std::pair<int, int>> halfEdge;
    std::vector<int> outgoingFace(mesh.vertices.size(), -1);
    std::vector<int> outgoingCorner(mesh.vertices.size(), -1);
    std::vector<std::size_t> valence(mesh.vertices.size(), 0);

    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
        const auto& face = mesh.faces[f];
        const int n = static_cast<int>(face.size());
        std::vector<double> alpha(n);
        alpha[0] = 0.25 + 5.0 / (4.0 * n);
        for (int j = 1; j < n; ++j)
            alpha[j] = (3.0 + 2.0 * std::cos(2.0 * std::numbers::pi * j / n)) / (4.0 * n);
        corner[f].resize(n);
        for (int i = 0; i < n; ++i) {
            glm::dvec3 p(0.0);
            for (int j = 0; j < n; ++j)
                p += alpha[j] * mesh.vertices[face[(i + j) % n]];
            corner[f][i] = static_cast<int>(out.vertices.size());
            out.vertices.push_back(p);
            halfEdge[key(face[i], face[(i + 1) % n])] = {int(f), i};
            outgoingFace[face[i]] = int(f);
            outgoingCorner[face[i]] = i;
            ++valence[face[i]];
        }
        out.faces.push_back(corner[f]);  // F-face
    }

    // E-faces: edge a→b in face f1 and b→a in face f2 give the quad
    // f1(b), f1(a), f2(a), f2(b), which runs against both F-faces along their new edges.
    for (std::size_t f1 = 0; f1 < mesh.faces.size(); ++f1) {
        const auto& face = mesh.faces[f1];
        const int n1 = int(face.size());
        for (int i1 = 0; i1 < n1; ++i1) {
            const int a = face[i1];
            const int b = face[(i1 + 1) % n1];
            if (a > b) continue;  // each undirected edge once, in a deterministic order
            const auto [f2, i2] = halfEdge.at(key(b, a));
            const int n2 = int(mesh.faces[f2].size());
            out.faces.push_back({corner[f1][(i1 + 1) % n1], corner[f1][i1],
                                 corner[f2][(i2 + 1) % n2], corner[f2][i2]});
        }
    }

    // V-faces: walk the faces around each vertex (from the face holding v→w to the one
    // holding w→v, which turns clockwise seen from outside) and emit them reversed.
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
        std::vector<int> ring;
        int f = outgoingFace[v];
        int i = outgoingCorner[v];
        const int start = f;
        do {
            ring.push_back(corner[f][i]);
            const auto& face = mesh.faces[f];
            const int w = face[(i + 1) % face.size()];
            const auto [g, j] = halfEdge.at(key(w, int(v)));
            // In g, v follows w: v's corner is j + 1.
            f = g;
            i = (j + 1) % int(mesh.faces[g].size());
        } while (f != start && ring.size() <= valence[v]);
        if (ring.size() != valence[v])
            throw std::invalid_argument("dooSabin: vertex " + std::to_string(v) +
                                        " is not manifold (its faces form more than one fan)");
        out.faces.emplace_back(ring.rbegin(), ring.rend());
    }
    return out;
}

}  // namespace

PolyMesh dooSabin(const PolyMesh& mesh, int levels) {
    if (levels < 0 || levels > 8)
        throw std::invalid_argument("dooSabin: levels must be in [0, 8], got " +
                                    std::to_string(levels));
    checkInput(mesh);
    PolyMesh current = mesh;
    for (int level = 0; level < levels; ++level)
        current = step(current);
    return current;
}

}  // namespace vsculpt::sketch
