// The only translation unit with CGAL in the subdivision code: it compiles slowly.
#include "vsculpt/sketch/ThreeSection.h"

// GCC 12 reports -Wmaybe-uninitialized inside CGAL's box-intersection code when it is inlined
// here (a false positive in the library); silence it for this file only.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <map>
#include <numeric>
#include <stdexcept>
#include <string>
#include <tuple>

namespace vsculpt::sketch {

namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using Kernel = CGAL::Exact_predicates_exact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;
using VertexIndex = Mesh::Vertex_index;
using FaceIndex = Mesh::Face_index;
using HalfedgeIndex = Mesh::Halfedge_index;

Mesh toMesh(const PolyMesh& solid, std::size_t which) {
    if (!isClosedOriented(solid))
        throw std::invalid_argument("intersectSolids: solid " + std::to_string(which) +
                                    " is not closed and oriented");
    Mesh mesh;
    std::vector<VertexIndex> vertices;
    for (const auto& p : solid.vertices)
        vertices.push_back(mesh.add_vertex({p.x, p.y, p.z}));
    for (const auto& face : solid.faces) {
        std::vector<VertexIndex> ring;
        for (int i : face)
            ring.push_back(vertices[i]);
        if (mesh.add_face(ring) == Mesh::null_face())
            throw std::invalid_argument("intersectSolids: solid " + std::to_string(which) +
                                        " is not a valid polygon mesh");
    }
    if (!PMP::triangulate_faces(mesh))
        throw std::invalid_argument("intersectSolids: solid " + std::to_string(which) +
                                    " has a face that cannot be triangulated");
    return mesh;
}

int findRoot(std::vector<int>& parent, int i) {
    while (parent[i] != i)
        i = parent[i] = parent[parent[i]];
    return i;
}

// Merges edge-connected coplanar triangles (exact test on the exact kernel) into n-gons.
PolyMesh mergeCoplanar(const Mesh& mesh) {
    std::map<FaceIndex, int> faceId;
    std::vector<FaceIndex> faces;
    for (FaceIndex f : mesh.faces()) {
        faceId[f] = int(faces.size());
        faces.push_back(f);
    }
    std::vector<Kernel::Plane_3> planes;
    for (FaceIndex f : faces) {
        HalfedgeIndex h = mesh.halfedge(f);
        planes.emplace_back(mesh.point(mesh.source(h)), mesh.point(mesh.target(h)),
                            mesh.point(mesh.target(mesh.next(h))));
    }
    std::vector<int> parent(faces.size());
    std::iota(parent.begin(), parent.end(), 0);
    for (HalfedgeIndex h : mesh.halfedges()) {
        const FaceIndex f = mesh.face(h), g = mesh.face(mesh.opposite(h));
        if (f == Mesh::null_face() || g == Mesh::null_face()) continue;
        const int a = faceId[f], b = faceId[g];
        // Oriented plane equality: same plane and same outward side.
        if (planes[a] == planes[b]) parent[findRoot(parent, a)] = findRoot(parent, b);
    }
    // Boundary loop of each group; a group whose boundary is not one simple loop keeps its
    // triangles.
    std::map<int, std::vector<HalfedgeIndex>> boundary;
    for (HalfedgeIndex h : mesh.halfedges()) {
        const FaceIndex f = mesh.face(h);
        const FaceIndex g = mesh.face(mesh.opposite(h));
        if (f == Mesh::null_face()) continue;
        const int group = findRoot(parent, faceId[f]);
        if (g == Mesh::null_face() || findRoot(parent, faceId[g]) != group)
            boundary[group].push_back(h);
    }
    std::map<VertexIndex, int> vertexId;
    PolyMesh out;
    auto idOf = [&](VertexIndex v) {
        auto [it, inserted] = vertexId.try_emplace(v, int(out.vertices.size()));
        if (inserted) {
            const auto& p = mesh.point(v);
            out.vertices.push_back(
                {CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())});
        }
        return it->second;
    };
    std::vector<char> merged(faces.size(), 0);
    for (const auto& [group, edges] : boundary) {
        std::map<VertexIndex, HalfedgeIndex> from;
        bool simple = true;
        for (HalfedgeIndex h : edges)
            if (!from.emplace(mesh.source(h), h).second) simple = false;
        std::vector<int> loop;
        if (simple) {
            HalfedgeIndex h = edges.front();
            do {
                loop.push_back(idOf(mesh.source(h)));
                auto it = from.find(mesh.target(h));
                if (it == from.end()) {
                    simple = false;
                    break;
                }
                h = it->second;
            } while (h != edges.front() && loop.size() <= edges.size());
            simple = simple && loop.size() == edges.size();
        }
        if (!simple) continue;
        out.faces.push_back(loop);
        for (std::size_t i = 0; i < faces.size(); ++i)
            if (findRoot(parent, int(i)) == group) merged[i] = 1;
    }
    for (std::size_t i = 0; i < faces.size(); ++i) {
        if (merged[i]) continue;
        std::vector<int> triangle;
        for (VertexIndex v : CGAL::vertices_around_face(mesh.halfedge(faces[i]), mesh))
            triangle.push_back(idOf(v));
        out.faces.push_back(triangle);
    }
    // A vertex on only two faces sits on the straight edge between them (left over where a
    // third, now merged, facet used to meet it); drop it so Doo–Sabin sees no 2-valent corner.
    std::vector<int> valence(out.vertices.size(), 0);
    for (const auto& face : out.faces)
        for (int v : face)
            ++valence[v];
    for (auto& face : out.faces) {
        std::vector<int> kept;
        for (int v : face)
            if (valence[v] > 2) kept.push_back(v);
        face = kept;
    }
    // Canonical order (vertices sorted by position, faces by their smallest vertex, each face
    // starting there): CGAL's internal order can vary from run to run, the result must not.
    std::vector<char> used(out.vertices.size(), 0);
    for (const auto& face : out.faces)
        for (int v : face)
            used[v] = 1;
    std::vector<int> order;
    for (std::size_t v = 0; v < out.vertices.size(); ++v)
        if (used[v]) order.push_back(int(v));
    std::sort(order.begin(), order.end(), [&](int a, int b) {
        const auto& p = out.vertices[a];
        const auto& q = out.vertices[b];
        return std::tie(p.x, p.y, p.z) < std::tie(q.x, q.y, q.z);
    });
    std::vector<int> remap(out.vertices.size(), -1);
    PolyMesh compact;
    for (int v : order) {
        remap[v] = int(compact.vertices.size());
        compact.vertices.push_back(out.vertices[v]);
    }
    for (auto face : out.faces) {
        for (int& v : face)
            v = remap[v];
        std::rotate(face.begin(), std::min_element(face.begin(), face.end()), face.end());
        compact.faces.push_back(face);
    }
    std::sort(compact.faces.begin(), compact.faces.end());
    return compact;
}

}  // namespace

PolyMesh intersectSolids(const std::vector<PolyMesh>& solids) {
    if (solids.empty()) throw std::invalid_argument("intersectSolids: no solids");
    Mesh result = toMesh(solids[0], 0);
    for (std::size_t i = 1; i < solids.size(); ++i) {
        Mesh other = toMesh(solids[i], i);
        Mesh out;
        if (!PMP::corefine_and_compute_intersection(result, other, out))
            throw std::runtime_error("intersectSolids: the Boolean intersection with solid " +
                                     std::to_string(i) + " failed");
        result = std::move(out);
    }
    if (result.number_of_faces() == 0)
        throw std::runtime_error("intersectSolids: the intersection is empty");
    return mergeCoplanar(result);
}

}  // namespace vsculpt::sketch
