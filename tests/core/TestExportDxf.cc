// SPDX-License-Identifier: MIT
// DXF export read back two ways: by a third-party reader (ezdxf, Debian's python3-ezdxf, run
// through python3) for entity counts, layers and coordinates, and by a group-code scan here.
// The ezdxf tests skip only when python3 or its ezdxf module is missing.
#include "vsculpt/core/ExportDxf.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace vsculpt::core {
namespace {

namespace fs = std::filesystem;

// A closed tetrahedron (4 triangles) with coordinates that are not short decimals.
Mesh tetrahedron() {
    Mesh m;
    m.positions = {{0.1, 0.2, 0.3}, {10.0 / 3.0, 0, 0}, {0, 7.25, 0}, {1e-3, 2e-3, 5.125}};
    m.indices = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
    return m;
}

Mesh singleTriangle() {
    Mesh m;
    m.positions = {{-1, -2, -3}, {4, 5, 6}, {7, -8, 9}};
    m.indices = {0, 1, 2};
    return m;
}

struct DxfFixture : ::testing::Test {
    fs::path dir;
    void SetUp() override {
        dir = fs::temp_directory_path() /
              ("vsculpt_dxf_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
               "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(dir);
    }
    void TearDown() override { fs::remove_all(dir); }
};

// Temporary files writeFileAtomically left in `dir` (it must leave none).
size_t leftoverTemporaryFiles(const fs::path& dir) {
    size_t n = 0;
    for (const auto& e : fs::directory_iterator(dir)) {
        const std::string name = e.path().filename().string();
        n += name.front() == '.' && name.ends_with(".tmp");
    }
    return n;
}

// Runs a python3 script and returns its output; status is 77 (the script's import guard) or
// 127 (the shell) when python3 or ezdxf is missing.
std::string runPython(const fs::path& dir, const std::string& script, int& status) {
    const fs::path py = dir / "read.py", out = dir / "read.out";
    std::ofstream(py) << "import sys\ntry:\n    import ezdxf\nexcept ImportError:\n"
                         "    sys.exit(77)\n"
                      << script;
    // Debian's interpreter first: python3-ezdxf installs there, and a python3 earlier on PATH
    // (pyenv, a venv) may not see it.
    for (const char* python : {"/usr/bin/python3", "python3"}) {
        const std::string cmd =
            std::string(python) + " '" + py.string() + "' > '" + out.string() + "' 2>&1";
        const int rc = std::system(cmd.c_str());
        status = WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
        if (status != 77 && status != 127) break;
    }
    std::ifstream in(out);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// Pairs of (group code, value) lines.
std::vector<std::pair<int, std::string>> groupCodes(const fs::path& path) {
    std::ifstream in(path);
    std::vector<std::pair<int, std::string>> out;
    std::string code, value;
    while (std::getline(in, code) && std::getline(in, value))
        out.emplace_back(std::stoi(code), value);
    return out;
}

TEST_F(DxfFixture, EzdxfReadsFacesPolylinesLayersAndCoordinates) {
    const fs::path path = dir / "sketch.dxf";
    const std::vector<Mesh> surfaces{tetrahedron(), singleTriangle()};
    const std::vector<std::vector<Vec3>> curves{
        {{0, 0, 0}, {1.5, 0, 0}, {1.5, 2.25, 0}},                       // open, planar
        {{0, 0, 0}, {3, 0, 1}, {3, 3, 2}, {0, 3, 3}, {0.5, 0.25, 4}}};  // closed, non-planar
    DxfOptions options;
    options.surfaceLayers = {"solid", "extra"};
    options.curveLayers = {"outline"};  // the second curve falls back to curveLayer
    options.closedCurves = {false, true};
    writeDxf(path, surfaces, curves, options);
    EXPECT_EQ(leftoverTemporaryFiles(dir), 0u);

    int status = 0;
    const std::string out = runPython(dir, R"(
doc = ezdxf.readfile(sys.argv[0].replace('read.py', 'sketch.dxf'))
msp = doc.modelspace()
faces = msp.query('3DFACE')
polys = msp.query('POLYLINE')
print('faces', len(faces))
print('polylines', len(polys))
print('solid', len(msp.query('3DFACE[layer=="solid"]')))
print('extra', len(msp.query('3DFACE[layer=="extra"]')))
print('outline', len(msp.query('POLYLINE[layer=="outline"]')))
print('curve', len(msp.query('POLYLINE[layer=="curve"]')))
# ezdxf adds the standard layers 0 and Defpoints itself.
print('layers', ' '.join(sorted(l.dxf.name for l in doc.layers if l.dxf.name not in ('0', 'Defpoints'))))
f = faces[0]
print('face0', repr(f.dxf.vtx0.x), repr(f.dxf.vtx1.y), repr(f.dxf.vtx2.x), repr(f.dxf.vtx3.x))
p = polys[1]
pts = list(p.points())
print('poly1', len(pts), int(p.is_3d_polyline), int(p.is_closed), repr(pts[4].x), repr(pts[4].y), repr(pts[4].z))
print('poly0', len(list(polys[0].points())), int(polys[0].is_closed))
print('units', doc.header.get('$INSUNITS', -1))
)",
                                      status);
    if (status == 77 || status == 127)
        GTEST_SKIP() << "python3 with ezdxf is not installed (apt-get install python3-ezdxf)";
    ASSERT_EQ(status, 0) << out;
    std::map<std::string, std::string> lines;
    std::istringstream in(out);
    for (std::string line; std::getline(in, line);) {
        const auto space = line.find(' ');
        lines[line.substr(0, space)] = line.substr(space + 1);
    }
    EXPECT_EQ(lines["faces"], "5");
    EXPECT_EQ(lines["polylines"], "2");
    EXPECT_EQ(lines["solid"], "4");
    EXPECT_EQ(lines["extra"], "1");
    EXPECT_EQ(lines["outline"], "1");
    EXPECT_EQ(lines["curve"], "1");
    EXPECT_EQ(lines["layers"], "curve extra outline solid");
    // Triangle 0 of the tetrahedron is (0, 2, 1); the 4th corner repeats the 3rd. 17 digits:
    // ezdxf parses the very doubles that were written.
    EXPECT_EQ(lines["face0"], "0.1 7.25 3.3333333333333335 3.3333333333333335");
    EXPECT_EQ(lines["poly1"], "5 1 1 0.5 0.25 4.0");
    EXPECT_EQ(lines["poly0"], "3 0");
    EXPECT_EQ(lines["units"], "4");
}

TEST_F(DxfFixture, EzdxfAuditFindsNoErrors) {
    const fs::path path = dir / "sketch.dxf";
    const std::vector<Mesh> surfaces{tetrahedron()};
    const std::vector<std::vector<Vec3>> curves{{{0, 0, 0}, {1, 1, 1}}};
    writeDxf(path, surfaces, curves);
    int status = 0;
    const std::string out = runPython(dir, R"(
doc = ezdxf.readfile(sys.argv[0].replace('read.py', 'sketch.dxf'))
auditor = doc.audit()
print(len(auditor.errors))
)",
                                      status);
    if (status == 77 || status == 127)
        GTEST_SKIP() << "python3 with ezdxf is not installed (apt-get install python3-ezdxf)";
    ASSERT_EQ(status, 0) << out;
    EXPECT_EQ(out, "0\n");
}

TEST_F(DxfFixture, GroupCodesFollowR12) {
    const fs::path path = dir / "codes.dxf";
    const std::vector<Mesh> surfaces{singleTriangle()};
    const std::vector<std::vector<Vec3>> curves{{{1, 2, 3}, {4, 5, 6}, {7, 8, 9}}};
    DxfOptions options;
    options.closedCurves = {true};
    writeDxf(path, surfaces, curves, options);
    const auto codes = groupCodes(path);
    ASSERT_GE(codes.size(), 4u);
    EXPECT_EQ(codes.front(), (std::pair<int, std::string>{0, "SECTION"}));
    EXPECT_EQ(codes.back(), (std::pair<int, std::string>{0, "EOF"}));
    // The 3DFACE: layer, then corners 10/20/30 … 13/23/33 in order, the 4th equal to the 3rd.
    size_t face = 0;
    while (face < codes.size() && codes[face] != std::pair<int, std::string>{0, "3DFACE"})
        ++face;
    ASSERT_LT(face + 13, codes.size());
    EXPECT_EQ(codes[face + 1], (std::pair<int, std::string>{8, "surface"}));
    const double expected[4][3] = {{-1, -2, -3}, {4, 5, 6}, {7, -8, 9}, {7, -8, 9}};
    for (int q = 0; q < 4; ++q)
        for (int a = 0; a < 3; ++a) {
            const auto& [code, value] = codes[face + 2 + 3 * q + a];
            EXPECT_EQ(code, 10 + q + 10 * a);
            EXPECT_EQ(std::stod(value), expected[q][a]);
        }
    // The POLYLINE: 66 = 1, flags 8 | 1 (3D, closed), three VERTEX with flag 32, then SEQEND.
    size_t poly = face;
    while (poly < codes.size() && codes[poly] != std::pair<int, std::string>{0, "POLYLINE"})
        ++poly;
    ASSERT_LT(poly, codes.size());
    int vertices = 0, seqend = 0, flags = -1, follow = -1;
    for (size_t i = poly + 1; i < codes.size() && codes[i].second != "ENDSEC"; ++i) {
        if (codes[i] == std::pair<int, std::string>{0, "VERTEX"}) {
            ++vertices;
            ASSERT_LT(i + 5, codes.size());
            EXPECT_EQ(codes[i + 2].first, 10);
            EXPECT_EQ(std::stod(codes[i + 2].second), 1.0 + 3 * (vertices - 1));
            EXPECT_EQ(codes[i + 5], (std::pair<int, std::string>{70, "32"}));
        }
        seqend += codes[i] == std::pair<int, std::string>{0, "SEQEND"};
        if (vertices == 0 && codes[i].first == 70) flags = std::stoi(codes[i].second);
        if (vertices == 0 && codes[i].first == 66) follow = std::stoi(codes[i].second);
    }
    EXPECT_EQ(vertices, 3);
    EXPECT_EQ(seqend, 1);
    EXPECT_EQ(flags, 9);
    EXPECT_EQ(follow, 1);
}

TEST_F(DxfFixture, ExportMeshWritesThroughTheSameWriter) {
    const fs::path path = dir / "sculpture.dxf";
    exportMesh(tetrahedron(), path);
    int faces = 0;
    for (const auto& [code, value] : groupCodes(path)) {
        faces += code == 0 && value == "3DFACE";
        if (code == 8) {
            EXPECT_EQ(value, "sculpture");
        }
    }
    EXPECT_EQ(faces, 4);
}

TEST_F(DxfFixture, BadInputThrowsNamingTheProblemAndLeavesNoFile) {
    const fs::path path = dir / "bad.dxf";
    Mesh broken = singleTriangle();
    broken.indices[2] = 7;
    const auto expectThrow = [&](std::span<const Mesh> s, std::span<const std::vector<Vec3>> c,
                                 const DxfOptions& o, const std::string& part) {
        try {
            writeDxf(path, s, c, o);
            ADD_FAILURE() << "no exception, expected: " << part;
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
        }
        EXPECT_FALSE(fs::exists(path));
        EXPECT_EQ(leftoverTemporaryFiles(dir), 0u);
    };
    const std::vector<Mesh> bad{broken};
    expectThrow(bad, {}, {}, "surface 0: triangle index 7 is out of range");
    const std::vector<std::vector<Vec3>> shortCurve{{{0, 0, 0}}};
    expectThrow({}, shortCurve, {}, "curve 0 has fewer than 2 points");
    const std::vector<std::vector<Vec3>> nanCurve{{{0, 0, 0}, {std::nan(""), 0, 0}}};
    expectThrow({}, nanCurve, {}, "curve 0 has a non-finite coordinate");
    DxfOptions badLayer;
    badLayer.curveLayer = "a/b";
    const std::vector<std::vector<Vec3>> ok{{{0, 0, 0}, {1, 0, 0}}};
    expectThrow({}, ok, badLayer, "layer name 'a/b'");
    expectThrow({}, {}, {}, "nothing to write");
}

TEST_F(DxfFixture, UnwritablePathThrowsExportError) {
    const std::vector<Mesh> surfaces{singleTriangle()};
    EXPECT_THROW(writeDxf(dir / "missing" / "x.dxf", surfaces, {}), ExportError);
}

}  // namespace
}  // namespace vsculpt::core
