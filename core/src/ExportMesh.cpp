// SPDX-License-Identifier: MIT
#include "vsculpt/core/ExportMesh.h"

#include "vsculpt/core/ExportDxf.h"
#include "vsculpt/core/WriteFileAtomically.h"

#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <cstring>
#include <mutex>
#include <sstream>

namespace vsculpt::core {

namespace {

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

std::ostringstream textOut() {
    std::ostringstream out;
    out.precision(9);
    return out;
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

// Each format is rendered in memory and written with writeFileAtomically: no library ever
// opens the output path, so no partial or foreign file can appear under the real name.

std::string writeObj(const Mesh& m) {
    std::ostringstream out = textOut();
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
    return std::move(out).str();
}

std::string writeStl(const Mesh& m) {
    std::ostringstream out;
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
    return std::move(out).str();
}

std::string writePly(const Mesh& m) {
    std::ostringstream out = textOut();
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
    return std::move(out).str();
}

std::string writeGlb(const Mesh& m, const std::filesystem::path& p) {
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
    std::ostringstream out;
    if (!writer.WriteGltfSceneToStream(&model, out, false, true))
        throw ExportError(p.string() + ": glTF writer failed");
    return std::move(out).str();
}

/// io::File writes only to a path it opens itself; its seekable archive format (grid offsets
/// patched in after each grid) is reached through Archive's protected stream writer, which an
/// in-memory stream also supports.
class VdbMemoryArchive : public openvdb::io::Archive {
  public:
    std::string write(const openvdb::GridPtrVec& grids) const {
        std::ostringstream out(std::ios::out | std::ios::binary);
        openvdb::io::Archive::write(out, grids, /*seekable=*/true);
        return std::move(out).str();
    }
};

std::string writeVdb(const Mesh& m, const ExportOptions& o) {
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
    return VdbMemoryArchive().write(openvdb::GridPtrVec{grid});
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
    std::string bytes;
    try {
        if (ext == ".obj")
            bytes = writeObj(mesh);
        else if (ext == ".stl")
            bytes = writeStl(mesh);
        else if (ext == ".ply")
            bytes = writePly(mesh);
        else if (ext == ".glb")
            bytes = writeGlb(mesh, path);
        else
            bytes = writeVdb(mesh, o);
    } catch (const ExportError&) {
        throw;
    } catch (const std::exception& e) {
        throw ExportError(path.string() + ": " + e.what());
    }
    try {
        // Not durable: an export is redone from the project, which is.
        writeFileAtomically(path, bytes, false);
    } catch (const FileWriteError& e) {
        throw ExportError(e.what());
    }
}

}  // namespace vsculpt::core
