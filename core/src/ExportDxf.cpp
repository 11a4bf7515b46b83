// SPDX-License-Identifier: MIT
#include "vsculpt/core/ExportDxf.h"

#include "vsculpt/core/WriteFileAtomically.h"

#include <cmath>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>

namespace vsculpt::core {

namespace {

const std::string& layerOf(const std::vector<std::string>& layers, const std::string& fallback,
                           size_t i) {
    return i < layers.size() ? layers[i] : fallback;
}

void requireLayerName(const std::string& name, const std::string& owner) {
    if (name.empty()) throw std::invalid_argument("writeDxf: " + owner + ": layer name is empty");
    for (char c : name)
        if (std::string_view("<>/\\\":;?*|=`").find(c) != std::string_view::npos ||
            static_cast<unsigned char>(c) < 32)
            throw std::invalid_argument("writeDxf: " + owner + ": layer name '" + name +
                                        "' holds a character DXF does not allow");
}

void requireFinite(const Vec3& p, const std::string& owner) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        throw std::invalid_argument("writeDxf: " + owner + " has a non-finite coordinate");
}

// Group code lines: the code, then the value, each on its own line.
void point(std::ostream& out, int code, const Vec3& p) {
    out << code << '\n'
        << p.x << '\n'
        << code + 10 << '\n'
        << p.y << '\n'
        << code + 20 << '\n'
        << p.z << '\n';
}

int insUnits(LengthUnit unit) {
    switch (unit) {
        case LengthUnit::Millimetre:
            return 4;
        case LengthUnit::Centimetre:
            return 5;
        case LengthUnit::Metre:
            return 6;
    }
    return 0;  // not reached: every unit is handled above
}

void writeLayerTable(std::ostream& out, const std::set<std::string>& layers) {
    out << "0\nSECTION\n2\nTABLES\n";
    // The LAYER entries name the CONTINUOUS line type, which R12 readers expect to be defined.
    out << "0\nTABLE\n2\nLTYPE\n70\n1\n"
           "0\nLTYPE\n2\nCONTINUOUS\n70\n0\n3\nSolid line\n72\n65\n73\n0\n40\n0.0\n"
           "0\nENDTAB\n";
    out << "0\nTABLE\n2\nLAYER\n70\n" << layers.size() << '\n';
    for (const std::string& name : layers)
        out << "0\nLAYER\n2\n" << name << "\n70\n0\n62\n7\n6\nCONTINUOUS\n";
    out << "0\nENDTAB\n0\nENDSEC\n";
}

}  // namespace

void writeDxf(const std::filesystem::path& path, std::span<const Mesh> surfaces,
              std::span<const std::vector<Vec3>> curves, const DxfOptions& options) {
    // Validate everything before the file is touched: bad input is the caller's, not the disk's.
    std::set<std::string> layers;
    size_t entities = 0;
    for (size_t s = 0; s < surfaces.size(); ++s) {
        const std::string owner = "surface " + std::to_string(s);
        const std::string& layer = layerOf(options.surfaceLayers, options.surfaceLayer, s);
        requireLayerName(layer, owner);
        const Mesh& m = surfaces[s];
        if (m.indices.size() % 3 != 0)
            throw std::invalid_argument("writeDxf: " + owner +
                                        ": index count is not a multiple of 3");
        for (uint32_t i : m.indices)
            if (i >= m.positions.size())
                throw std::invalid_argument("writeDxf: " + owner + ": triangle index " +
                                            std::to_string(i) + " is out of range");
        for (const Vec3& p : m.positions)
            requireFinite(p, owner);
        if (m.triangleCount() > 0) layers.insert(layer);
        entities += m.triangleCount();
    }
    for (size_t c = 0; c < curves.size(); ++c) {
        const std::string owner = "curve " + std::to_string(c);
        const std::string& layer = layerOf(options.curveLayers, options.curveLayer, c);
        requireLayerName(layer, owner);
        if (curves[c].size() < 2)
            throw std::invalid_argument("writeDxf: " + owner + " has fewer than 2 points");
        for (const Vec3& p : curves[c])
            requireFinite(p, owner);
        layers.insert(layer);
        ++entities;
    }
    if (entities == 0)
        throw std::invalid_argument("writeDxf: nothing to write (no triangles and no curves)");

    std::ostringstream out;
    out.precision(std::numeric_limits<double>::max_digits10);
    const ExportFrame& frame = options.frame;
    out << "0\nSECTION\n2\nHEADER\n9\n$ACADVER\n1\nAC1009\n9\n$INSUNITS\n70\n"
        << insUnits(frame.units) << "\n0\nENDSEC\n";
    writeLayerTable(out, layers);
    out << "0\nSECTION\n2\nENTITIES\n";
    for (size_t s = 0; s < surfaces.size(); ++s) {
        const Mesh& m = surfaces[s];
        const std::string& layer = layerOf(options.surfaceLayers, options.surfaceLayer, s);
        for (size_t t = 0; t < m.triangleCount(); ++t) {
            out << "0\n3DFACE\n8\n" << layer << '\n';
            for (int q = 0; q < 4; ++q)
                point(out, 10 + q, frame.point(m.positions[m.indices[3 * t + std::min(q, 2)]]));
        }
    }
    for (size_t c = 0; c < curves.size(); ++c) {
        const std::string& layer = layerOf(options.curveLayers, options.curveLayer, c);
        const bool closed = c < options.closedCurves.size() && options.closedCurves[c];
        // 66 = 1: vertices follow; 70 bit 8: 3D polyline, bit 1: closed.
        out << "0\nPOLYLINE\n8\n" << layer << "\n66\n1\n";
        point(out, 10, Vec3(0.0));
        out << "70\n" << (8 | (closed ? 1 : 0)) << '\n';
        for (const Vec3& p : curves[c]) {
            out << "0\nVERTEX\n8\n" << layer << '\n';
            point(out, 10, frame.point(p));
            out << "70\n32\n";  // 32: a 3D polyline vertex
        }
        out << "0\nSEQEND\n8\n" << layer << '\n';
    }
    out << "0\nENDSEC\n0\nEOF\n";
    try {
        writeFileAtomically(path, std::move(out).str(), false);
    } catch (const FileWriteError& e) {
        throw ExportError(e.what());
    }
}

}  // namespace vsculpt::core
