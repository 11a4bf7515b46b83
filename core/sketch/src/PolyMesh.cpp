#include "vsculpt/sketch/PolyMesh.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <map>
#include <utility>

namespace vsculpt::sketch {

namespace {
// Directed edge → number of faces using it in that direction.
std::map<std::pair<int, int>, int> directedEdges(const PolyMesh& mesh) {
    std::map<std::pair<int, int>, int> edges;
    for (const auto& face : mesh.faces)
        for (std::size_t i = 0; i < face.size(); ++i)
            ++edges[{face[i], face[(i + 1) % face.size()]}];
    return edges;
}
}  // namespace

std::size_t countEdges(const PolyMesh& mesh) {
    std::map<std::pair<int, int>, int> undirected;
    for (const auto& [edge, uses] : directedEdges(mesh))
        undirected[{std::min(edge.first, edge.second), std::max(edge.first, edge.second)}] += uses;
    return undirected.size();
}

long eulerCharacteristic(const PolyMesh& mesh) {
    return static_cast<long>(mesh.vertices.size()) - static_cast<long>(countEdges(mesh)) +
           static_cast<long>(mesh.faces.size());
}

bool isClosedOriented(const PolyMesh& mesh) {
    const int n = static_cast<int>(mesh.vertices.size());
    for (const auto& face : mesh.faces) {
        if (face.size() < 3) return false;
        for (int index : face)
            if (index < 0 || index >= n) return false;
    }
    const auto edges = directedEdges(mesh);
    for (const auto& [edge, uses] : edges) {
        if (uses != 1 || edge.first == edge.second) return false;
        const auto reverse = edges.find({edge.second, edge.first});
        if (reverse == edges.end() || reverse->second != 1) return false;
    }
    return true;
}

double enclosedVolume(const PolyMesh& mesh) {
    double sixTimesVolume = 0.0;
    for (const auto& face : mesh.faces) {
        if (face.size() < 3) continue;
        const glm::dvec3& a = mesh.vertices[face[0]];
        for (std::size_t i = 1; i + 1 < face.size(); ++i)
            sixTimesVolume +=
                glm::dot(a, glm::cross(mesh.vertices[face[i]], mesh.vertices[face[i + 1]]));
    }
    return sixTimesVolume / 6.0;
}

}  // namespace vsculpt::sketch
