// SPDX-License-Identifier: MIT
// Axes and units of exports (issue #16), read back by third-party readers: Assimp for OBJ, STL,
// PLY and GLB with no post-processing (nothing that could turn or scale what was written),
// the GLB's JSON chunk by nlohmann::json, DXF by its group codes, VDB by OpenVDB.
//
// The sculpture is lopsided on every axis (a stroke up +z, a longer one out along +x, a
// shorter one along -y), so a mirror, a wrong turn or a swapped axis changes the box.
#include "../TestFiles.h"
#include "vsculpt/app/Cli.h"
#include "vsculpt/core/ExportDxf.h"
#include "vsculpt/core/ExportMesh.h"
#include "vsculpt/studio/Session.h"

#include <assimp/scene.h>
#include <gtest/gtest.h>
#include <openvdb/openvdb.h>
#include <unistd.h>
#include <assimp/Importer.hpp>
#include <nlohmann/json.hpp>

#include <array>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>

using namespace vsculpt;
using core::Aabb;
using core::LengthUnit;
using core::UpAxis;
using core::Vec3;

namespace {

constexpr double kSpacingMm = 1.5;

// Written out here rather than taken from core::ExportFrame, so the test does not share a
// mistake with the code it checks: Y-up is (x, y, z) -> (x, z, -y).
Vec3 expectedPoint(const Vec3& mm, UpAxis up, double mmPerUnit) {
    const Vec3 turned = up == UpAxis::Y ? Vec3(mm.x, mm.z, -mm.y) : mm;
    return turned / mmPerUnit;
}

Aabb expectedBox(const Aabb& mm, UpAxis up, double mmPerUnit) {
    Aabb box;
    for (int corner = 0; corner < 8; ++corner)
        box.expand(
            expectedPoint(Vec3(corner & 1 ? mm.max.x : mm.min.x, corner & 2 ? mm.max.y : mm.min.y,
                               corner & 4 ? mm.max.z : mm.min.z),
                          up, mmPerUnit));
    return box;
}

double mmPer(LengthUnit u) {
    return u == LengthUnit::Metre ? 1000 : u == LengthUnit::Centimetre ? 10 : 1;
}

/// What a reader got: triangles as positions, with the normal at the highest vertex.
struct ReadBack {
    std::vector<std::array<Vec3, 3>> triangles;
    Aabb box;
    std::optional<Vec3> normalAtTop;  ///< unit normal at the vertex furthest along `up`
    bool identityTransforms = true;   ///< every node of the scene graph has no transform

    double signedVolume() const {
        double v = 0;
        for (const auto& t : triangles)
            v += glm::dot(t[0], glm::cross(t[1], t[2]));
        return v / 6;
    }
    /// Every edge used exactly once in each direction: closed, manifold, consistently wound.
    /// Corners are matched by position, so STL's unshared corners count as shared.
    bool closedAndConsistent() const {
        std::map<std::array<double, 3>, size_t> ids;
        const auto id = [&](const Vec3& p) {
            return ids.try_emplace({p.x, p.y, p.z}, ids.size()).first->second;
        };
        std::map<std::pair<size_t, size_t>, int> directed;
        for (const auto& t : triangles)
            for (int e = 0; e < 3; ++e)
                ++directed[{id(t[e]), id(t[(e + 1) % 3])}];
        for (const auto& [edge, n] : directed) {
            const auto back = directed.find({edge.second, edge.first});
            if (n != 1 || back == directed.end() || back->second != 1) return false;
        }
        return !triangles.empty();
    }
};

void collectTransforms(const aiNode* node, bool& identity) {
    identity &= node->mTransformation.IsIdentity();
    for (unsigned c = 0; c < node->mNumChildren; ++c)
        collectTransforms(node->mChildren[c], identity);
}

ReadBack readWithAssimp(const std::filesystem::path& path, UpAxis up) {
    Assimp::Importer importer;
    // 0: no post-processing step at all, so the numbers are the file's own.
    const aiScene* scene = importer.ReadFile(path.string(), 0);
    ReadBack r;
    if (!scene) {
        ADD_FAILURE() << path << ": " << importer.GetErrorString();
        return r;
    }
    collectTransforms(scene->mRootNode, r.identityTransforms);
    const int upAxis = up == UpAxis::Y ? 1 : 2;
    double top = -1e300;
    for (unsigned mi = 0; mi < scene->mNumMeshes; ++mi) {
        const aiMesh* m = scene->mMeshes[mi];
        const auto at = [&](unsigned i) {
            return Vec3(m->mVertices[i].x, m->mVertices[i].y, m->mVertices[i].z);
        };
        for (unsigned v = 0; v < m->mNumVertices; ++v) {
            const Vec3 p = at(v);
            r.box.expand(p);
            if (m->HasNormals() && p[upAxis] > top) {
                top = p[upAxis];
                r.normalAtTop = Vec3(m->mNormals[v].x, m->mNormals[v].y, m->mNormals[v].z);
            }
        }
        for (unsigned f = 0; f < m->mNumFaces; ++f) {
            const aiFace& face = m->mFaces[f];
            if (face.mNumIndices != 3) {
                ADD_FAILURE() << path << ": a face with " << face.mNumIndices << " corners";
                continue;
            }
            r.triangles.push_back(
                {at(face.mIndices[0]), at(face.mIndices[1]), at(face.mIndices[2])});
        }
    }
    return r;
}

using vsculpt::test::readFile;

/// The JSON chunk of a GLB (glTF 2.0 binary container: 12-byte header, then chunks).
nlohmann::json glbJson(const std::filesystem::path& path) {
    const std::string bytes = readFile(path);
    uint32_t header[5] = {};
    if (bytes.size() < sizeof header) return {};
    std::memcpy(header, bytes.data(), sizeof header);
    EXPECT_EQ(std::string(bytes.data(), 4), "glTF");
    EXPECT_EQ(header[1], 2u);           // container version
    EXPECT_EQ(header[4], 0x4E4F534Au);  // "JSON"
    return nlohmann::json::parse(bytes.substr(20, header[3]));
}

struct ExportAxes : ::testing::Test {
    static inline core::Mesh mesh;
    static inline Aabb boxMm;
    static inline double volumeMm3 = 0;
    static inline std::filesystem::path dir;

    static void SetUpTestSuite() {
        core::SculptConfig cfg;
        cfg.sphereRadiusMm = 20;
        cfg.polygonizer.gridN = 64;
        studio::Session s(cfg);
        s.setSize(5);
        s.stroke({Vec3(0, 0, 0), Vec3(0, 0, 35), Vec3(0, 0, 70)}, false);  // tall: +z
        s.stroke({Vec3(0, 0, 0), Vec3(25, 0, 0), Vec3(50, 0, 0)}, false);  // long: +x
        s.stroke({Vec3(0, 0, 0), Vec3(0, -30, 0)}, false);                 // short: -y
        mesh = s.wholeMesh(kSpacingMm);
        boxMm = core::meshBounds(mesh);
        volumeMm3 = core::meshVolume(mesh);
        dir = std::filesystem::temp_directory_path() /
              ("vsculpt-export-axes-" + std::to_string(::getpid()));
        std::filesystem::create_directories(dir);
    }
    static void TearDownTestSuite() { std::filesystem::remove_all(dir); }
};

TEST_F(ExportAxes, TheSculptureIsLopsidedOnEveryAxis) {
    ASSERT_TRUE(core::analyzeTopology(mesh).watertight());
    ASSERT_GT(volumeMm3, 0);
    // Tallest along z, then x; every axis reaches further one way than the other.
    EXPECT_GT(boxMm.max.z - boxMm.min.z, boxMm.max.x - boxMm.min.x + 10);
    EXPECT_GT(boxMm.max.x - boxMm.min.x, boxMm.max.y - boxMm.min.y + 10);
    EXPECT_GT(boxMm.max.z, -boxMm.min.z + 30);
    EXPECT_GT(boxMm.max.x, -boxMm.min.x + 20);
    EXPECT_GT(-boxMm.min.y, boxMm.max.y + 10);
}

struct Case {
    const char* ext;
    std::optional<UpAxis> up;  ///< asked for (unset: the format's default)
    std::optional<LengthUnit> units;
    UpAxis wantUp;  ///< what the file must hold
    LengthUnit wantUnits;
};

TEST_F(ExportAxes, AssimpReadsEachFormatUpright_InItsUnit_ClosedAndOutward) {
    const Case cases[] = {
        // The defaults (docs/playback.md): glTF as its specification says, OBJ as its readers
        // assume, STL and PLY as slicers and CAD assume.
        {".glb", {}, {}, UpAxis::Y, LengthUnit::Metre},
        {".obj", {}, {}, UpAxis::Y, LengthUnit::Millimetre},
        {".stl", {}, {}, UpAxis::Z, LengthUnit::Millimetre},
        {".ply", {}, {}, UpAxis::Z, LengthUnit::Millimetre},
        // Asked for explicitly.
        {".glb", UpAxis::Y, LengthUnit::Metre, UpAxis::Y, LengthUnit::Metre},
        {".obj", UpAxis::Z, LengthUnit::Centimetre, UpAxis::Z, LengthUnit::Centimetre},
        {".stl", UpAxis::Y, LengthUnit::Metre, UpAxis::Y, LengthUnit::Metre},
        {".ply", UpAxis::Y, LengthUnit::Centimetre, UpAxis::Y, LengthUnit::Centimetre},
        {".obj", {}, LengthUnit::Metre, UpAxis::Y, LengthUnit::Metre},
    };
    int n = 0;
    for (const Case& c : cases) {
        const double per = mmPer(c.wantUnits);
        const auto path = dir / ("case" + std::to_string(n++) + c.ext);
        SCOPED_TRACE(path.filename().string() + " up " + (c.wantUp == UpAxis::Y ? "y" : "z") +
                     ", mm per unit " + std::to_string(per));
        core::ExportOptions o;
        o.up = c.up;
        o.units = c.units;
        core::exportMesh(mesh, path, o);
        const ReadBack r = readWithAssimp(path, c.wantUp);
        ASSERT_EQ(r.triangles.size(), mesh.triangleCount());
        // Assimp put no axis conversion of its own into the scene graph (and glTF has no node
        // transform), so the vertices are the whole story.
        EXPECT_TRUE(r.identityTransforms);

        // Tall direction: +Y or +Z; +X stays +X; the sculpture's -y reach lands on file +z
        // when Y-up (a rotation, not a mirror).
        const int upAxis = c.wantUp == UpAxis::Y ? 1 : 2, depth = c.wantUp == UpAxis::Y ? 2 : 1;
        const Vec3 size = r.box.max - r.box.min;
        EXPECT_GT(size[upAxis], size[0]);
        EXPECT_GT(size[upAxis], size[depth]);
        EXPECT_GT(r.box.max[upAxis], -r.box.min[upAxis]);
        EXPECT_GT(r.box.max.x, -r.box.min.x);
        if (c.wantUp == UpAxis::Y) {
            EXPECT_GT(r.box.max.z, -r.box.min.z);
        } else {
            EXPECT_GT(-r.box.min.y, r.box.max.y);
        }

        // Box: the mm box turned and divided by the unit, to float precision (far below a
        // grid spacing); its size is the mm size times the unit factor.
        const Aabb want = expectedBox(boxMm, c.wantUp, per);
        const double tol = 1e-4 / per;
        for (int a = 0; a < 3; ++a) {
            EXPECT_NEAR(r.box.min[a], want.min[a], tol) << "axis " << a;
            EXPECT_NEAR(r.box.max[a], want.max[a], tol) << "axis " << a;
        }
        const Vec3 sizeMm = boxMm.max - boxMm.min;
        EXPECT_NEAR(size[upAxis], sizeMm.z / per, kSpacingMm / per);
        EXPECT_NEAR(size[0], sizeMm.x / per, kSpacingMm / per);
        EXPECT_NEAR(size[depth], sizeMm.y / per, kSpacingMm / per);

        // Closed, consistently wound, outward: the signed volume is the mm volume in units^3.
        EXPECT_TRUE(r.closedAndConsistent());
        const double volume = r.signedVolume();
        EXPECT_GT(volume, 0);
        EXPECT_NEAR(volume, volumeMm3 / (per * per * per), 1e-5 * volumeMm3 / (per * per * per));

        // Normals turned with the positions: the topmost vertex faces up.
        ASSERT_TRUE(r.normalAtTop.has_value());
        EXPECT_GT((*r.normalAtTop)[upAxis], 0.8);
    }
}

TEST_F(ExportAxes, GlbHasNoNodeTransformAndItsBoundsAreTheVertices) {
    const auto path = dir / "bounds.glb";
    core::exportMesh(mesh, path);
    const nlohmann::json j = glbJson(path);
    ASSERT_TRUE(j.is_object());
    EXPECT_EQ(j["asset"]["version"], "2.0");
    ASSERT_EQ(j["nodes"].size(), 1u);
    for (const char* t : {"matrix", "translation", "rotation", "scale"})
        EXPECT_FALSE(j["nodes"][0].contains(t)) << t;
    const int accessor = j["meshes"][0]["primitives"][0]["attributes"]["POSITION"];
    const nlohmann::json& a = j["accessors"][accessor];
    ASSERT_TRUE(a.contains("min") && a.contains("max"));
    const ReadBack r = readWithAssimp(path, UpAxis::Y);
    const Aabb want = expectedBox(boxMm, UpAxis::Y, 1000);
    for (int i = 0; i < 3; ++i) {
        // The accessor's bounds are the float vertices' bounds (the glTF rule), which are the
        // metre box of the sculpture.
        EXPECT_EQ(a["min"][i].get<double>(), r.box.min[i]) << i;
        EXPECT_EQ(a["max"][i].get<double>(), r.box.max[i]) << i;
        EXPECT_NEAR(a["min"][i].get<double>(), want.min[i], 1e-7) << i;
        EXPECT_NEAR(a["max"][i].get<double>(), want.max[i], 1e-7) << i;
    }
}

TEST_F(ExportAxes, GlbRefusesAnyFrameButYUpMetres) {
    for (const auto& [up, units] :
         {std::pair<std::optional<UpAxis>, std::optional<LengthUnit>>{UpAxis::Z, {}},
          {{}, LengthUnit::Millimetre},
          {UpAxis::Y, LengthUnit::Centimetre}}) {
        core::ExportOptions o;
        o.up = up;
        o.units = units;
        const auto path = dir / "refused.glb";
        try {
            core::exportMesh(mesh, path, o);
            ADD_FAILURE() << "no exception";
        } catch (const core::ExportError& e) {
            EXPECT_NE(std::string(e.what()).find("glTF is always +Y up in metres"),
                      std::string::npos)
                << e.what();
        }
        EXPECT_FALSE(std::filesystem::exists(path));
    }
}

/// Group codes of a DXF as (code, value) pairs.
std::vector<std::pair<int, std::string>> groupCodes(const std::filesystem::path& path) {
    std::ifstream in(path);
    std::vector<std::pair<int, std::string>> out;
    std::string code, value;
    while (std::getline(in, code) && std::getline(in, value))
        out.emplace_back(std::stoi(code), value);
    return out;
}

struct Dxf {
    int insUnits = -1;
    std::vector<std::array<Vec3, 3>> faces;
    std::vector<std::vector<Vec3>> polylines;
};

Dxf readDxf(const std::filesystem::path& path) {
    const auto codes = groupCodes(path);
    Dxf d;
    for (size_t i = 0; i + 1 < codes.size(); ++i)
        if (codes[i] == std::pair<int, std::string>{9, "$INSUNITS"})
            d.insUnits = std::stoi(codes[i + 1].second);
    // Corner k of an entity is codes 10+k, 20+k, 30+k.
    const auto corner = [&](size_t from, int k) {
        Vec3 p(std::nan(""));
        for (size_t i = from + 1; i < codes.size() && codes[i].first != 0; ++i)
            for (int a = 0; a < 3; ++a)
                if (codes[i].first == 10 * (a + 1) + k) p[a] = std::stod(codes[i].second);
        return p;
    };
    for (size_t i = 0; i < codes.size(); ++i) {
        if (codes[i] == std::pair<int, std::string>{0, "3DFACE"})
            d.faces.push_back({corner(i, 0), corner(i, 1), corner(i, 2)});
        if (codes[i] == std::pair<int, std::string>{0, "POLYLINE"}) d.polylines.emplace_back();
        if (codes[i] == std::pair<int, std::string>{0, "VERTEX"})
            d.polylines.back().push_back(corner(i, 0));
    }
    return d;
}

TEST_F(ExportAxes, DxfWritesItsUnitToInsunitsAndTurnsFacesAndCurves) {
    struct DxfCase {
        std::optional<UpAxis> up;
        std::optional<LengthUnit> units;
        UpAxis wantUp;
        double per;
        int insUnits;
    };
    for (const DxfCase& c : {DxfCase{{}, {}, UpAxis::Z, 1, 4},
                             DxfCase{UpAxis::Y, LengthUnit::Metre, UpAxis::Y, 1000, 6},
                             DxfCase{{}, LengthUnit::Centimetre, UpAxis::Z, 10, 5}}) {
        SCOPED_TRACE("units code " + std::to_string(c.insUnits));
        const auto path = dir / "sculpture.dxf";
        core::ExportOptions o;
        o.up = c.up;
        o.units = c.units;
        core::exportMesh(mesh, path, o);
        const Dxf d = readDxf(path);
        EXPECT_EQ(d.insUnits, c.insUnits);
        ASSERT_EQ(d.faces.size(), mesh.triangleCount());
        ReadBack r;
        for (const auto& f : d.faces) {
            r.triangles.push_back(f);
            for (const Vec3& p : f)
                r.box.expand(p);
        }
        const Aabb want = expectedBox(boxMm, c.wantUp, c.per);
        for (int a = 0; a < 3; ++a) {
            EXPECT_NEAR(r.box.min[a], want.min[a], 1e-9);
            EXPECT_NEAR(r.box.max[a], want.max[a], 1e-9);
        }
        EXPECT_TRUE(r.closedAndConsistent());
        EXPECT_NEAR(r.signedVolume(), volumeMm3 / (c.per * c.per * c.per),
                    1e-9 * volumeMm3 / (c.per * c.per * c.per));
    }
    // Sketch curves go through the same frame as the surface.
    core::DxfOptions options;
    options.frame = {UpAxis::Y, LengthUnit::Centimetre};
    const std::vector<std::vector<Vec3>> curves{{Vec3(10, 20, 30), Vec3(-40, 50, -60)}};
    writeDxf(dir / "curves.dxf", std::span<const core::Mesh>(&mesh, 1), curves, options);
    const Dxf d = readDxf(dir / "curves.dxf");
    EXPECT_EQ(d.insUnits, 5);
    ASSERT_EQ(d.polylines.size(), 1u);
    ASSERT_EQ(d.polylines[0].size(), 2u);
    EXPECT_EQ(d.polylines[0][0], Vec3(1, 3, -2));
    EXPECT_EQ(d.polylines[0][1], Vec3(-4, -6, -5));
}

TEST_F(ExportAxes, VdbVoxelSizeFollowsTheUnitAndTheGridIsTurned) {
    const auto path = dir / "sculpture.vdb";
    core::ExportOptions o;
    o.voxelSizeMm = kSpacingMm;
    o.up = UpAxis::Y;
    o.units = LengthUnit::Metre;
    core::exportMesh(mesh, path, o);
    openvdb::initialize();
    openvdb::io::File file(path.string());
    file.open();
    const openvdb::GridBase::Ptr base = file.readGrid("sculpture");
    file.close();
    const auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
    ASSERT_TRUE(grid);
    EXPECT_NEAR(grid->voxelSize()[0], kSpacingMm / 1000, 1e-15);
    EXPECT_EQ(grid->metaValue<std::string>("units"), "m");
    EXPECT_EQ(grid->metaValue<std::string>("up_axis"), "y");
    const auto acc = grid->getConstAccessor();
    const auto sdf = [&](double x, double y, double z) {
        return acc.getValue(openvdb::Coord::round(grid->worldToIndex(openvdb::Vec3d(x, y, z))));
    };
    EXPECT_LT(sdf(0, 0, 0), 0);
    EXPECT_LT(sdf(0, 0.060, 0), 0);   // the +z stroke, now up
    EXPECT_GT(sdf(0, -0.060, 0), 0);  // nothing below
    EXPECT_LT(sdf(0, 0, 0.028), 0);   // the -y stroke, now towards +z
    EXPECT_GT(sdf(0, 0, -0.028), 0);
    EXPECT_LT(sdf(0.045, 0, 0), 0);  // +x stays +x
    EXPECT_GT(sdf(-0.045, 0, 0), 0);
}

struct CliRun {
    int code;
    std::string out, err;
};

CliRun cli(std::vector<std::string> args) {
    args.insert(args.begin(), "vsculpt");
    std::vector<const char*> argv;
    for (const std::string& a : args)
        argv.push_back(a.c_str());
    std::ostringstream out, err;
    const int code = app::runCli(int(argv.size()), argv.data(), out, err);
    return {code, out.str(), err.str()};
}

TEST_F(ExportAxes, PlayTakesUpAndUnits_StatsStayInObjectMillimetres) {
    const auto script = dir / "tall.vsc";
    std::ofstream(script) << "tool add\nsize 6\nstroke 0 0 30  0 0 90\n";
    const std::string stl = (dir / "tall.stl").string(), glb = (dir / "tall.glb").string(),
                      stats = (dir / "tall.json").string();
    const CliRun r = cli({"play", script.string(), "--no-progress", "--up", "Y", "--units", "CM",
                          "--out", stl, "--out", glb, "--stats", stats});
    ASSERT_EQ(r.code, 0) << r.err;
    // The .glb cannot follow --units cm; the run goes on and says so.
    EXPECT_NE(r.err.find("--out " + glb + ": glTF is always +Y up in metres"), std::string::npos)
        << r.err;
    EXPECT_EQ(r.err.find("--out " + stl + ": glTF"), std::string::npos) << r.err;
    const nlohmann::json j = nlohmann::json::parse(readFile(stats));
    const Vec3 lo(j["bbox_mm"]["min"][0], j["bbox_mm"]["min"][1], j["bbox_mm"]["min"][2]);
    const Vec3 hi(j["bbox_mm"]["max"][0], j["bbox_mm"]["max"][1], j["bbox_mm"]["max"][2]);
    EXPECT_GT(hi.z, 90);  // Z-up mm: the stroke's top
    const double volumeMm3 = j["volume_mm3"];
    for (const auto& [path, per] : {std::pair<std::string, double>{stl, 10}, {glb, 1000}}) {
        SCOPED_TRACE(path);
        const Aabb want = expectedBox(Aabb{lo, hi}, UpAxis::Y, per);
        const ReadBack back = readWithAssimp(path, UpAxis::Y);
        for (int a = 0; a < 3; ++a) {
            EXPECT_NEAR(back.box.min[a], want.min[a], 1e-4 / per);
            EXPECT_NEAR(back.box.max[a], want.max[a], 1e-4 / per);
        }
        const double volume = volumeMm3 / (per * per * per);
        EXPECT_NEAR(back.signedVolume(), volume, 1e-5 * volume);
    }
    // Unknown axes and units are refused before any work.
    for (const auto& bad : {std::pair<std::string, std::string>{"--up", "x"}, {"--units", "in"}}) {
        const CliRun b =
            cli({"play", script.string(), "--no-progress", bad.first, bad.second, "--out", stl});
        EXPECT_EQ(b.code, 2) << bad.first << " " << bad.second;
        EXPECT_NE(b.err.find(bad.first), std::string::npos) << b.err;
    }
}

}  // namespace
