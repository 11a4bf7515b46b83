// SPDX-License-Identifier: MIT
// Every export is read back: OBJ, STL, PLY and GLB by Assimp (a third-party loader from
// Debian), DXF by counting its 3DFACE entities, VDB by OpenVDB's own reader. Axes and units
// are tested in TestExportAxes.cc.
#include "vsculpt/core/ExportMesh.h"
#include "vsculpt/studio/Session.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <gtest/gtest.h>
#include <openvdb/openvdb.h>
#include <assimp/Importer.hpp>

#include <filesystem>
#include <fstream>

using namespace vsculpt;
using core::Vec3;

namespace {

struct Export : ::testing::Test {
    static inline core::Mesh mesh;
    static inline std::filesystem::path dir;
    static void SetUpTestSuite() {
        core::SculptConfig cfg;
        cfg.sphereRadiusMm = 25;
        cfg.polygonizer.gridN = 64;
        studio::Session s(cfg);
        s.setSize(5);
        s.stroke({Vec3(-40, 0, 10), Vec3(0, 0, 30), Vec3(40, 0, 10)}, false);
        mesh = s.wholeMesh(1.5);
        dir = std::filesystem::temp_directory_path() /
              ("vsculpt-export-" + std::to_string(::getpid()));
        std::filesystem::create_directories(dir);
    }
    static void TearDownTestSuite() { std::filesystem::remove_all(dir); }
};

void expectBoxNear(const aiScene* scene, const core::Aabb& want, double tol) {
    core::Aabb got;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m)
        for (unsigned v = 0; v < scene->mMeshes[m]->mNumVertices; ++v) {
            const aiVector3D& p = scene->mMeshes[m]->mVertices[v];
            got.expand(Vec3(p.x, p.y, p.z));
        }
    for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(got.min[a], want.min[a], tol);
        EXPECT_NEAR(got.max[a], want.max[a], tol);
    }
}

size_t faces(const aiScene* scene) {
    size_t n = 0;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m)
        n += scene->mMeshes[m]->mNumFaces;
    return n;
}

TEST_F(Export, ObjStlPlyGlbLoadInAssimp) {
    ASSERT_GT(mesh.triangleCount(), 1000u);
    const core::Aabb box = core::meshBounds(mesh);
    for (const char* ext : {".obj", ".stl", ".ply", ".glb"}) {
        const auto path = dir / (std::string("sculpture") + ext);
        core::exportMesh(mesh, path);
        Assimp::Importer importer;
        const aiScene* scene = importer.ReadFile(path.string(), aiProcess_JoinIdenticalVertices);
        ASSERT_NE(scene, nullptr) << ext << ": " << importer.GetErrorString();
        EXPECT_EQ(faces(scene), mesh.triangleCount()) << ext;
        // Each format in its default frame: the mm box turned to it (a quarter turn maps box
        // corners to box corners) and scaled.
        const core::ExportFrame frame = core::exportFrame(path, {});
        core::Aabb want;
        want.expand(frame.point(box.min));
        want.expand(frame.point(box.max));
        expectBoxNear(scene, want, 1e-3 / core::mmPerUnit(frame.units));
        if (std::string(ext) != ".stl") {
            unsigned vertices = 0;
            for (unsigned m = 0; m < scene->mNumMeshes; ++m)
                vertices += scene->mMeshes[m]->mNumVertices;
            EXPECT_EQ(vertices, mesh.positions.size()) << ext;
            EXPECT_TRUE(scene->mMeshes[0]->HasNormals()) << ext;
        }
    }
}

TEST_F(Export, DxfHasOne3dFacePerTriangle) {
    const auto path = dir / "sculpture.dxf";
    core::exportMesh(mesh, path);
    std::ifstream in(path);
    std::string line;
    size_t facesFound = 0;
    bool eof = false;
    while (std::getline(in, line)) {
        facesFound += line == "3DFACE";
        eof |= line == "EOF";
    }
    EXPECT_EQ(facesFound, mesh.triangleCount());
    EXPECT_TRUE(eof);
}

TEST_F(Export, VdbIsALevelSetOfTheSculpture) {
    const auto path = dir / "sculpture.vdb";
    core::ExportOptions o;
    o.voxelSizeMm = 1.5;
    core::exportMesh(mesh, path, o);
    openvdb::initialize();
    openvdb::io::File file(path.string());
    file.open();
    const openvdb::GridBase::Ptr base = file.readGrid("sculpture");
    file.close();
    const auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
    ASSERT_TRUE(grid);
    EXPECT_EQ(grid->getGridClass(), openvdb::GRID_LEVEL_SET);
    EXPECT_NEAR(grid->voxelSize()[0], 1.5, 1e-12);
    const auto acc = grid->getConstAccessor();
    const auto idx = [&](const Vec3& p) {
        return openvdb::Coord::round(grid->worldToIndex(openvdb::Vec3d(p.x, p.y, p.z)));
    };
    EXPECT_LT(acc.getValue(idx(Vec3(0, 0, 0))), 0);   // inside the sphere
    EXPECT_GT(acc.getValue(idx(Vec3(0, 0, 60))), 0);  // outside
    const openvdb::CoordBBox bbox = grid->evalActiveVoxelBoundingBox();
    const core::Aabb box = core::meshBounds(mesh);
    EXPECT_NEAR(bbox.min().x() * 1.5, box.min.x, 6 * 1.5);  // narrow band of 3 voxels
    EXPECT_NEAR(bbox.max().z() * 1.5, box.max.z, 6 * 1.5);
}

TEST_F(Export, BadExportsAreRefusedAndLeaveNothingBehind) {
    EXPECT_THROW(core::exportMesh(mesh, dir / "x.fbx"), core::ExportError);
    EXPECT_THROW(core::exportMesh(core::Mesh{}, dir / "x.obj"), core::ExportError);
    EXPECT_THROW(core::exportMesh(mesh, "/nonexistent-dir/x.obj"), core::ExportError);
    EXPECT_FALSE(std::filesystem::exists(dir / "x.obj"));
}

}  // namespace
