#include "TeddyCdt.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Constrained_triangulation_face_base_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <deque>
#include <stdexcept>
#include <string>

namespace vsculpt::sketch::detail {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<int, Kernel>;
// Face info: nesting depth (number of constraint crossings from the infinite face), -1 unset.
using FaceInfoBase = CGAL::Triangulation_face_base_with_info_2<int, Kernel>;
using FaceBase = CGAL::Constrained_triangulation_face_base_2<Kernel, FaceInfoBase>;
using Tds = CGAL::Triangulation_data_structure_2<VertexBase, FaceBase>;
// No_constraint_intersection_tag: crossing constraints throw instead of silently inserting
// Steiner points that the callers' index-based meshes could not represent.
using Cdt =
    CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds, CGAL::No_constraint_intersection_tag>;
}  // namespace

std::vector<std::array<int, 3>> triangulateLoops(const std::vector<glm::dvec2>& points,
                                                 const std::vector<std::vector<int>>& loops) {
    Cdt cdt;
    std::vector<Cdt::Vertex_handle> handles(points.size());
    for (const auto& loop : loops) {
        if (loop.size() < 3)
            throw std::invalid_argument("triangulateLoops: a loop has fewer than 3 points");
        for (int index : loop) {
            if (index < 0 || static_cast<std::size_t>(index) >= points.size())
                throw std::invalid_argument("triangulateLoops: loop index out of range");
            if (handles[index] != Cdt::Vertex_handle()) continue;
            handles[index] = cdt.insert(Cdt::Point(points[index].x, points[index].y));
            handles[index]->info() = index;
        }
    }
    // Coincident points share one CGAL vertex; the index maps would then disagree.
    for (std::size_t i = 0; i < handles.size(); ++i)
        if (handles[i] != Cdt::Vertex_handle() && handles[i]->info() != static_cast<int>(i))
            throw std::invalid_argument("triangulateLoops: points " + std::to_string(i) + " and " +
                                        std::to_string(handles[i]->info()) + " coincide");
    try {
        for (const auto& loop : loops)
            for (std::size_t i = 0; i < loop.size(); ++i)
                cdt.insert_constraint(handles[loop[i]], handles[loop[(i + 1) % loop.size()]]);
    } catch (const Cdt::Intersection_of_constraints_exception&) {
        throw std::invalid_argument("triangulateLoops: loop edges intersect");
    } catch (const CGAL::Failure_exception&) {
        throw std::invalid_argument("triangulateLoops: loop edges intersect");
    }
    if (cdt.dimension() < 2)
        throw std::invalid_argument("triangulateLoops: all points are collinear");

    // Flood fill depths from the infinite face; crossing a constraint increments the depth.
    for (auto face = cdt.all_faces_begin(); face != cdt.all_faces_end(); ++face)
        face->info() = -1;
    std::deque<std::pair<Cdt::Face_handle, int>> queue{{cdt.infinite_face(), 0}};
    while (!queue.empty()) {
        auto [face, depth] = queue.front();
        queue.pop_front();
        if (face->info() != -1) continue;
        face->info() = depth;
        for (int i = 0; i < 3; ++i) {
            const Cdt::Face_handle next = face->neighbor(i);
            if (next->info() != -1) continue;
            if (cdt.is_constrained({face, i}))
                queue.push_back({next, depth + 1});
            else
                queue.push_front({next, depth});
        }
    }

    std::vector<std::array<int, 3>> triangles;
    for (auto face = cdt.finite_faces_begin(); face != cdt.finite_faces_end(); ++face)
        if (face->info() % 2 == 1)
            triangles.push_back(
                {face->vertex(0)->info(), face->vertex(1)->info(), face->vertex(2)->info()});
    return triangles;
}

}  // namespace vsculpt::sketch::detail
