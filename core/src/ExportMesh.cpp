// SPDX-License-Identifier: MIT
#include "vsculpt/core/ExportMesh.h"

#include "vsculpt/core/ExportDxf.h"

#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <mutex>

namespace vsculpt::core {

namespace {

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

/// Writes through a temporary file and renames it over `path` once complete.
template <typename Fn>
void writeAtomically(const std::filesystem::path& path, Fn&& write) {
    const std::filesystem::path tmp = path.string() + ".part";
    try {
        write(tmp);
    } catch (const ExportError&) {
        std::filesystem::remove(tmp);
        throw;
    } catch (const std::exception& e) {
        std::filesystem::remove(tmp);
        throw ExportError(path.string() + ": " + e.what());
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        std::filesystem::remove(tmp);
        throw ExportError(path.string() + ": cannot write: " + ec.message());
    }
}

std::ofstream openOut(const std::filesystem::path& p, bool binary) {
    std::ofstream out(p, binary ? std::ios::binary : std::ios::out);
    if (!out) throw ExportError(p.string() + ": cannot open for writing");
    out.precision(9);
    return out;
}

void finish(std::ofstream& out, const std::filesystem::path& p) {
    out.flush();
    if (!out) throw ExportError(p.string() + ": write failed (disk full?)");
}

template <typename T>
void put(std::ostream& out, T v) {
    out.write(reinterpret_cast<const char*>(&v), sizeof v);
}

Vec3 faceNormal(const Mesh& m, size_t t) {
    const Vec3 a = m.positions[m.indices[3 * t]], b = m.positions[m.indices[3 * t + 1]],
               c = m.positions[m.indices[3 * t + 2]];
    const Vec3 n = glm::cross(b - a, c - a);
    const double l = glm::length(n);
    return l > 0 ? n / l : Vec3(0.0);
}

void writeObj(const Mesh& m, const std::filesystem::path& p) {
    std::ofstream out = openOut(p, false);
    out << "# vsculpt mesh, millimetres\n";
    for (const Vec3& v : m.positions)
        out << "v " << v.x << ' ' << v.y << ' ' << v.z << '\n';
    const bool normals = m.normals.size() == m.positions.size();
    if (normals)
        for (const Vec3& n : m.normals)
            out << "vn " << n.x << ' ' << n.y << ' ' << n.z << '\n';
    for (size_t t = 0; t < m.triangleCount(); ++t) {
        out << 'f';
        for (int q = 0; q < 3; ++q) {
            const uint32_t i = m.indices[3 * t + q] + 1;
            out << ' ' << i;
            if (normals) out << "//" << i;
        }
        out << '\n';
    }
    finish(out, p);
}

void writeStl(const Mesh& m, const std::filesystem::path& p) {
    std::ofstream out = openOut(p, true);
    char header[80] = {};
    std::snprintf(header, sizeof header, "vsculpt binary STL, millimetres");
    out.write(header, sizeof header);
    put(out, uint32_t(m.triangleCount()));
    for (size_t t = 0; t < m.triangleCount(); ++t) {
        const Vec3 n = faceNormal(m, t);
        put(out, float(n.x));
        put(out, float(n.y));
        put(out, float(n.z));
        for (int q = 0; q < 3; ++q) {
            const Vec3& v = m.positions[m.indices[3 * t + q]];
            put(out, float(v.x));
            put(out, float(v.y));
            put(out, float(v.z));
        }
        put(out, uint16_t(0));
    }
    finish(out, p);
}

void writePly(const Mesh& m, const std::filesystem::path& p) {
    std::ofstream out = openOut(p, true);
    const bool normals = m.normals.size() == m.positions.size();
    out << "ply\nformat binary_little_endian 1.0\ncomment vsculpt mesh, millimetres\n"
        << "element vertex " << m.positions.size() << "\n"
        << "property float x\nproperty float y\nproperty float z\n";
    if (normals) out << "property float nx\nproperty float ny\nproperty float nz\n";
    out << "element face " << m.triangleCount() << "\n"
        << "property list uchar int vertex_indices\nend_header\n";
    for (size_t i = 0; i < m.positions.size(); ++i) {
        put(out, float(m.positions[i].x));
        put(out, float(m.positions[i].y));
        put(out, float(m.positions[i].z));
        if (normals) {
            put(out, float(m.normals[i].x));
            put(out, float(m.normals[i].y));
            put(out, float(m.normals[i].z));
        }
    }
    for (size_t t = 0; t < m.triangleCount(); ++t) {
        put(out, uint8_t(3));
        for (int q = 0; q < 3; ++q)
            put(out, int32_t(m.indices[3 * t + q]));
    }
    finish(out, p);
}

void writeGlb(const Mesh& m, const std::filesystem::path& p) {
    tinygltf::Model model;
    model.asset.version = "2.0";
    model.asset.generator = "vsculpt";
    const bool normals = m.normals.size() == m.positions.size();
    tinygltf::Buffer buffer;
    auto append = [&](const void* data, size_t bytes) {
        const size_t offset = buffer.data.size();
        buffer.data.resize(offset + bytes);
        std::memcpy(buffer.data.data() + offset, data, bytes);
        while (buffer.data.size() % 4)
            buffer.data.push_back(0);
        return offset;
    };
    std::vector<float> pos, nrm;
    std::vector<double> lo(3, 1e300), hi(3, -1e300);
    for (const Vec3& v : m.positions)
        for (int a = 0; a < 3; ++a) {
            pos.push_back(float(v[a]));
            lo[a] = std::min(lo[a], double(float(v[a])));
            hi[a] = std::max(hi[a], double(float(v[a])));
        }
    for (const Vec3& n : m.normals)
        for (int a = 0; a < 3; ++a)
            nrm.push_back(float(n[a]));
    auto view = [&](size_t offset, size_t bytes, int target) {
        tinygltf::BufferView v;
        v.buffer = 0;
        v.byteOffset = offset;
        v.byteLength = bytes;
        v.target = target;
        model.bufferViews.push_back(v);
        return int(model.bufferViews.size() - 1);
    };
    auto accessor = [&](int viewIndex, int componentType, int type, size_t count) {
        tinygltf::Accessor a;
        a.bufferView = viewIndex;
        a.componentType = componentType;
        a.type = type;
        a.count = count;
        model.accessors.push_back(a);
        return int(model.accessors.size() - 1);
    };
    tinygltf::Primitive prim;
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    const int posView =
        view(append(pos.data(), pos.size() * 4), pos.size() * 4, TINYGLTF_TARGET_ARRAY_BUFFER);
    const int posAcc =
        accessor(posView, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, m.positions.size());
    model.accessors[posAcc].minValues = lo;
    model.accessors[posAcc].maxValues = hi;
    prim.attributes["POSITION"] = posAcc;
    if (normals) {
        const int nView =
            view(append(nrm.data(), nrm.size() * 4), nrm.size() * 4, TINYGLTF_TARGET_ARRAY_BUFFER);
        prim.attributes["NORMAL"] =
            accessor(nView, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, m.positions.size());
    }
    const int iView = view(append(m.indices.data(), m.indices.size() * 4), m.indices.size() * 4,
                           TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    prim.indices = accessor(iView, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR,
                            m.indices.size());
    model.buffers.push_back(std::move(buffer));
    tinygltf::Mesh mesh;
    mesh.name = "sculpture";
    mesh.primitives.push_back(prim);
    model.meshes.push_back(mesh);
    tinygltf::Node node;
    node.mesh = 0;
    node.name = "sculpture (millimetres)";
    node.scale = {0.001, 0.001, 0.001};  // glTF is in metres
    model.nodes.push_back(node);
    tinygltf::Scene scene;
    scene.nodes.push_back(0);
    model.scenes.push_back(scene);
    model.defaultScene = 0;
    tinygltf::TinyGLTF writer;
    if (!writer.WriteGltfSceneToFile(&model, p.string(), true, true, false, true))
        throw ExportError(p.string() + ": glTF writer failed");
}

void writeVdb(const Mesh& m, const std::filesystem::path& p, const ExportOptions& o) {
    static std::once_flag once;
    std::call_once(once, [] { openvdb::initialize(); });
    const auto xform = openvdb::math::Transform::createLinearTransform(o.voxelSizeMm);
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> tris;
    for (const Vec3& v : m.positions)  // meshToLevelSet takes world-space points
        points.emplace_back(float(v.x), float(v.y), float(v.z));
    for (size_t t = 0; t < m.triangleCount(); ++t)
        tris.emplace_back(m.indices[3 * t], m.indices[3 * t + 1], m.indices[3 * t + 2]);
    openvdb::FloatGrid::Ptr grid = openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(
        *xform, points, tris, float(o.narrowBandVoxels));
    grid->setName("sculpture");
    grid->insertMeta("units", openvdb::StringMetadata("mm"));
    openvdb::io::File file(p.string());
    openvdb::GridPtrVec grids{grid};
    file.write(grids);
    file.close();
}

}  // namespace

const std::vector<std::string>& exportExtensions() {
    static const std::vector<std::string> e = {".obj", ".stl", ".ply", ".glb", ".dxf", ".vdb"};
    return e;
}

void exportMesh(const Mesh& mesh, const std::filesystem::path& path, const ExportOptions& o) {
    const std::string ext = lower(path.extension().string());
    if (std::find(exportExtensions().begin(), exportExtensions().end(), ext) ==
        exportExtensions().end())
        throw ExportError(path.string() + ": unknown export format '" + ext +
                          "' (use .obj, .stl, .ply, .glb, .dxf or .vdb)");
    if (mesh.triangleCount() == 0)
        throw ExportError(path.string() + ": nothing to export: the mesh is empty");
    if (ext == ".dxf") {  // ExportDxf writes atomically itself
        DxfOptions options;
        options.surfaceLayer = "sculpture";
        try {
            writeDxf(path, std::span<const Mesh>(&mesh, 1), {}, options);
        } catch (const std::invalid_argument& e) {
            throw ExportError(path.string() + ": " + e.what());
        }
        return;
    }
    writeAtomically(path, [&](const std::filesystem::path& tmp) {
        if (ext == ".obj")
            writeObj(mesh, tmp);
        else if (ext == ".stl")
            writeStl(mesh, tmp);
        else if (ext == ".ply")
            writePly(mesh, tmp);
        else if (ext == ".glb")
            writeGlb(mesh, tmp);
        else
            writeVdb(mesh, tmp, o);
    });
}

}  // namespace vsculpt::core
