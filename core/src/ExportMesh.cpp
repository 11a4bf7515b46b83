// SPDX-License-Identifier: MIT
#include "vsculpt/core/ExportMesh.h"

#include "VdbMesh.h"
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

/// "millimetres, +Z up": what a reader of a file without a unit field needs to know.
std::string frameNote(const ExportFrame& f) {
    const char* unit = f.units == LengthUnit::Millimetre   ? "millimetres"
                       : f.units == LengthUnit::Centimetre ? "centimetres"
                                                           : "metres";
    return std::string(unit) + ", +" + (f.up == UpAxis::Y ? "Y" : "Z") + " up";
}

/// Every writer below writes the mesh it is given as is: the frame is applied once, here.
Mesh inFrame(const Mesh& m, const ExportFrame& f) {
    Mesh out;
    out.indices = m.indices;
    out.positions.reserve(m.positions.size());
    for (const Vec3& p : m.positions)
        out.positions.push_back(f.point(p));
    out.normals.reserve(m.normals.size());
    for (const Vec3& n : m.normals)
        out.normals.push_back(f.direction(n));
    return out;
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

std::string writeObj(const Mesh& m, const ExportFrame& f) {
    std::ostringstream out = textOut();
    out << "# vsculpt mesh, " << frameNote(f) << "\n";
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

std::string writeStl(const Mesh& m, const ExportFrame& f) {
    std::ostringstream out;
    char header[80] = {};
    // Never starting with "solid": readers take such a file for ASCII STL.
    std::snprintf(header, sizeof header, "vsculpt binary STL, %s", frameNote(f).c_str());
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

std::string writePly(const Mesh& m, const ExportFrame& f) {
    std::ostringstream out = textOut();
    const bool normals = m.normals.size() == m.positions.size();
    out << "ply\nformat binary_little_endian 1.0\ncomment vsculpt mesh, " << frameNote(f) << "\n"
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
    // No node transform: the vertices are already Y-up metres, so readers that ignore node
    // transforms, or bake them differently, still get the sculpture standing at its size.
    tinygltf::Node node;
    node.mesh = 0;
    node.name = "sculpture";
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

std::string writeVdb(const Mesh& m, const ExportOptions& o, const ExportFrame& f) {
    initializeOpenVdb();
    const auto xform =
        openvdb::math::Transform::createLinearTransform(o.voxelSizeMm / mmPerUnit(f.units));
    const auto [points, tris] = toVdbMesh(m);  // meshToLevelSet takes world-space points
    openvdb::FloatGrid::Ptr grid = openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(
        *xform, points, tris, float(o.narrowBandVoxels));
    grid->setName("sculpture");
    // VDB has no axis or unit convention: the metadata is the only place a reader can learn them.
    grid->insertMeta("units", openvdb::StringMetadata(toString(f.units)));
    grid->insertMeta("up_axis", openvdb::StringMetadata(toString(f.up)));
    return VdbMemoryArchive().write(openvdb::GridPtrVec{grid});
}

}  // namespace

UpAxis parseUpAxis(std::string_view text) {
    const std::string t = lower(std::string(text));
    if (t == "y") return UpAxis::Y;
    if (t == "z") return UpAxis::Z;
    throw std::invalid_argument("unknown up axis '" + std::string(text) + "' (use y or z)");
}

LengthUnit parseLengthUnit(std::string_view text) {
    const std::string t = lower(std::string(text));
    if (t == "mm") return LengthUnit::Millimetre;
    if (t == "cm") return LengthUnit::Centimetre;
    if (t == "m") return LengthUnit::Metre;
    throw std::invalid_argument("unknown unit '" + std::string(text) + "' (use mm, cm or m)");
}

const char* toString(UpAxis up) {
    return up == UpAxis::Y ? "y" : "z";
}

const char* toString(LengthUnit unit) {
    switch (unit) {
        case LengthUnit::Millimetre:
            return "mm";
        case LengthUnit::Centimetre:
            return "cm";
        case LengthUnit::Metre:
            return "m";
    }
    return "?";
}

double mmPerUnit(LengthUnit unit) {
    switch (unit) {
        case LengthUnit::Millimetre:
            return 1;
        case LengthUnit::Centimetre:
            return 10;
        case LengthUnit::Metre:
            return 1000;
    }
    return 1;
}

// Dividing by the exact mm-per-unit (not multiplying by an inexact 0.1 or 0.001) rounds each
// coordinate once, so 150 mm is 0.15 m to the last bit.
Vec3 ExportFrame::point(const Vec3& p) const {
    return direction(p) / mmPerUnit(units);
}

Vec3 ExportFrame::direction(const Vec3& v) const {
    return up == UpAxis::Y ? Vec3(v.x, v.z, -v.y) : v;
}

bool formatFixesFrame(const std::filesystem::path& path) {
    return lower(path.extension().string()) == ".glb";
}

ExportFrame exportFrame(const std::filesystem::path& path, const ExportOptions& o) {
    const std::string ext = lower(path.extension().string());
    if (std::find(exportExtensions().begin(), exportExtensions().end(), ext) ==
        exportExtensions().end())
        throw ExportError(path.string() + ": unknown export format '" + ext +
                          "' (use .obj, .stl, .ply, .glb, .dxf or .vdb)");
    ExportFrame f;
    if (formatFixesFrame(path)) {
        if ((o.up && *o.up != UpAxis::Y) || (o.units && *o.units != LengthUnit::Metre))
            throw ExportError(path.string() +
                              ": glTF is always +Y up in metres (glTF 2.0 specification); "
                              "leave up and units unset for .glb");
        return {UpAxis::Y, LengthUnit::Metre};
    }
    f.up = o.up.value_or(ext == ".obj" ? UpAxis::Y : UpAxis::Z);
    f.units = o.units.value_or(LengthUnit::Millimetre);
    return f;
}

const std::vector<std::string>& exportExtensions() {
    static const std::vector<std::string> e = {".obj", ".stl", ".ply", ".glb", ".dxf", ".vdb"};
    return e;
}

void exportMesh(const Mesh& mesh, const std::filesystem::path& path, const ExportOptions& o) {
    const ExportFrame frame = exportFrame(path, o);
    const std::string ext = lower(path.extension().string());
    if (mesh.triangleCount() == 0)
        throw ExportError(path.string() + ": nothing to export: the mesh is empty");
    if (ext == ".dxf") {  // ExportDxf writes atomically itself
        DxfOptions options;
        options.surfaceLayer = "sculpture";
        options.frame = frame;
        try {
            writeDxf(path, std::span<const Mesh>(&mesh, 1), {}, options);
        } catch (const std::invalid_argument& e) {
            throw ExportError(path.string() + ": " + e.what());
        }
        return;
    }
    std::string bytes;
    try {
        Mesh turned;
        if (!frame.identity()) turned = inFrame(mesh, frame);
        const Mesh& m = frame.identity() ? mesh : turned;
        if (ext == ".obj")
            bytes = writeObj(m, frame);
        else if (ext == ".stl")
            bytes = writeStl(m, frame);
        else if (ext == ".ply")
            bytes = writePly(m, frame);
        else if (ext == ".glb")
            bytes = writeGlb(m, path);
        else
            bytes = writeVdb(m, o, frame);
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
