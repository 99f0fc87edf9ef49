// Loading SCENE arguments (src/cubeao/scene/import.h): small files written to a temp directory with
// known triangles, malformed files that must end in a cubeao::Error naming the file (never a crash),
// the real scenes of ../shared/scenes and assimp-testmodels (skipped when absent) and builtin:NAME.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <random>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "cubeao/core/error.h"
#include "cubeao/scene/builtin.h"
#include "cubeao/scene/import.h"
#include "cubeao/scene/scene.h"
#include "test_util.h"
#include "test_paths.h"

namespace fs = std::filesystem;
using namespace cubeao;
using namespace cubeao::test;

namespace {

// Triangles as corner positions, each rotated to start at its smallest corner (keeps the winding),
// sorted: equal for two meshes with the same triangles whatever their vertex and index order.
using Triangle = std::array<std::array<float, 3>, 3>;
std::vector<Triangle> triangleMultiset(const std::vector<glm::vec3>& positions,
                                       const std::vector<std::uint32_t>& indices) {
    std::vector<Triangle> out;
    for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
        Triangle tri;
        for (int k = 0; k < 3; ++k) {
            const glm::vec3 p = positions.at(indices[t + k]);
            tri[k] = {p.x, p.y, p.z};
        }
        std::rotate(tri.begin(), std::min_element(tri.begin(), tri.end()), tri.end());
        out.push_back(tri);
    }
    std::sort(out.begin(), out.end());
    return out;
}
std::vector<Triangle> triangleMultiset(const Scene& s) { return triangleMultiset(s.positions, s.indices); }

double totalArea(const Scene& s) {
    double area = 0.0;
    for (std::size_t t = 0; t < s.indices.size(); t += 3) {
        const glm::dvec3 a(s.positions[s.indices[t]]), b(s.positions[s.indices[t + 1]]),
            c(s.positions[s.indices[t + 2]]);
        area += 0.5 * glm::length(glm::cross(b - a, c - a));
    }
    return area;
}

void expectVec3Near(const glm::vec3& actual, const glm::vec3& expected, float tol) {
    EXPECT_NEAR(actual.x, expected.x, tol);
    EXPECT_NEAR(actual.y, expected.y, tol);
    EXPECT_NEAR(actual.z, expected.z, tol);
}

// Every loaded scene, whatever its source, must satisfy these.
void expectWellFormed(const Scene& s) {
    ASSERT_GT(s.triangleCount(), 0u);
    ASSERT_EQ(s.indices.size() % 3, 0u);
    ASSERT_EQ(s.normals.size(), s.positions.size());
    for (std::uint32_t i : s.indices) ASSERT_LT(i, s.vertexCount());
    for (std::size_t i = 0; i < s.vertexCount(); ++i) {
        ASSERT_TRUE(std::isfinite(s.positions[i].x) && std::isfinite(s.positions[i].y) &&
                    std::isfinite(s.positions[i].z))
            << "vertex " << i;
        ASSERT_NEAR(glm::length(s.normals[i]), 1.0f, 1e-5f) << "vertex " << i;
    }
    EXPECT_EQ(s.hash, geometryHash(s.positions, s.indices));
}

const std::vector<glm::vec3> kQuad = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
const std::vector<std::uint32_t> kQuadIndices = {0, 1, 2, 0, 2, 3};

constexpr const char* kQuadObj =
    "# unit square in z = 0\n"
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
    "f 1 2 3\nf 1 3 4\n";

}  // namespace

// ---- formats -------------------------------------------------------------------------------------

TEST(ImportObj, QuadWithoutNormals) {
    TempDir dir;
    const std::string path = dir.write("quad.obj", kQuadObj);
    const Scene s = loadScene(path);
    expectWellFormed(s);
    EXPECT_EQ(s.source, path);
    EXPECT_EQ(s.triangleCount(), 2u);
    EXPECT_EQ(s.vertexCount(), 4u);
    EXPECT_TRUE(s.problems.normalsComputed);
    for (const glm::vec3& n : s.normals) expectVec3Near(n, glm::vec3(0, 0, 1), 1e-6f);
    EXPECT_EQ(triangleMultiset(s), triangleMultiset(kQuad, kQuadIndices));
    EXPECT_EQ(s.bounds.min, glm::vec3(0, 0, 0));
    EXPECT_EQ(s.bounds.max, glm::vec3(1, 1, 0));
}

TEST(ImportObj, QuadWithFileNormals) {
    // The file's normal is deliberately not the face normal (+z), so a computed one would show.
    TempDir dir;
    const std::string path = dir.write("quadn.obj",
                                       "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                       "vn 0 0.6 0.8\n"
                                       "f 1//1 2//1 3//1\nf 1//1 3//1 4//1\n");
    const Scene s = loadScene(path);
    expectWellFormed(s);
    EXPECT_EQ(s.triangleCount(), 2u);
    EXPECT_FALSE(s.problems.normalsComputed);
    for (const glm::vec3& n : s.normals) expectVec3Near(n, glm::vec3(0, 0.6f, 0.8f), 1e-6f);
}

TEST(ImportObj, PolygonFacesAreFanTriangulated) {
    // A convex pentagon (shoelace area 7) and a quad (area 1) next to it.
    TempDir dir;
    const std::string path = dir.write("poly.obj",
                                       "v 0 0 0\nv 2 0 0\nv 3 1 0\nv 1 3 0\nv -1 1 0\n"
                                       "v 5 0 0\nv 6 0 0\nv 6 1 0\nv 5 1 0\n"
                                       "f 1 2 3 4 5\n"
                                       "f 6 7 8 9\n");
    const Scene s = loadScene(path);
    expectWellFormed(s);
    EXPECT_EQ(s.triangleCount(), 5u);  // 3 from the pentagon, 2 from the quad
    const std::vector<glm::vec3> p = {{0, 0, 0}, {2, 0, 0}, {3, 1, 0}, {1, 3, 0}, {-1, 1, 0},
                                      {5, 0, 0}, {6, 0, 0}, {6, 1, 0}, {5, 1, 0}};
    EXPECT_EQ(triangleMultiset(s), triangleMultiset(p, {0, 1, 2, 0, 2, 3, 0, 3, 4, 5, 6, 7, 5, 7, 8}));
    EXPECT_NEAR(totalArea(s), 8.0, 1e-6);
}

TEST(ImportObj, NegativeIndicesCountFromTheLastVertex) {
    TempDir dir;
    const std::string path = dir.write("rel.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf -3 -2 -1\nv 0 1 0\nf -4 -2 -1\n");
    const Scene s = loadScene(path);
    expectWellFormed(s);
    EXPECT_EQ(triangleMultiset(s), triangleMultiset(kQuad, kQuadIndices));
}

TEST(ImportObj, NonManifoldFinKeepsEveryTriangle) {
    // Three triangles on the edge (0,0,0)-(1,0,0): a complex edge that OpenMesh's TriMesh would
    // refuse the third face for. The soup importer keeps all three.
    TempDir dir;
    const std::string path = dir.write("fin.obj",
                                       "v 0 0 0\nv 1 0 0\nv 0.5 1 0\nv 0.5 0 1\nv 0.5 0 -1\n"
                                       "f 1 2 3\nf 2 1 4\nf 1 2 5\n");
    const Scene s = loadScene(path);
    expectWellFormed(s);
    EXPECT_EQ(s.triangleCount(), 3u);
    const std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 0}, {0.5f, 1, 0}, {0.5f, 0, 1}, {0.5f, 0, -1}};
    EXPECT_EQ(triangleMultiset(s), triangleMultiset(p, {0, 1, 2, 1, 0, 3, 0, 1, 4}));
}

TEST(ImportPly, AsciiQuad) {
    TempDir dir;
    const std::string path = dir.write("quad.ply",
                                       "ply\nformat ascii 1.0\n"
                                       "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                                       "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
                                       "0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n");
    const Scene s = loadScene(path);
    expectWellFormed(s);
    EXPECT_EQ(s.triangleCount(), 2u);
    EXPECT_TRUE(s.problems.normalsComputed);
    EXPECT_EQ(triangleMultiset(s), triangleMultiset(kQuad, kQuadIndices));
}

TEST(ImportOff, Quad) {
    TempDir dir;
    const std::string path = dir.write("quad.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n");
    const Scene s = loadScene(path);
    expectWellFormed(s);
    EXPECT_EQ(s.triangleCount(), 2u);
    EXPECT_EQ(triangleMultiset(s), triangleMultiset(kQuad, kQuadIndices));
    for (const glm::vec3& n : s.normals) expectVec3Near(n, glm::vec3(0, 0, 1), 1e-6f);
}

namespace {
std::string stlFacet(const std::array<glm::vec3, 3>& v) {
    std::string s = "facet normal 0 0 1\n outer loop\n";
    for (const glm::vec3& p : v)
        s += "  vertex " + std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) + "\n";
    return s + " endloop\nendfacet\n";
}
}  // namespace

TEST(ImportStl, AsciiQuadSharesRepeatedCorners) {
    // STL writes every corner per facet: 6 corners, 4 distinct positions. OpenMesh's STL reader
    // already merges identical corners, so repair finds no duplicates left; the count of vertices
    // is what matters.
    TempDir dir;
    const std::string path =
        dir.write("quad.stl", "solid quad\n" + stlFacet({kQuad[0], kQuad[1], kQuad[2]}) +
                                  stlFacet({kQuad[0], kQuad[2], kQuad[3]}) + "endsolid quad\n");
    const Scene s = loadScene(path);
    expectWellFormed(s);
    EXPECT_EQ(s.triangleCount(), 2u);
    EXPECT_EQ(s.vertexCount(), 4u);
    EXPECT_EQ(s.problems.duplicateVertices, 0u);
    EXPECT_TRUE(s.problems.normalsComputed);  // STL facet normals are per face, not per vertex
    EXPECT_EQ(triangleMultiset(s), triangleMultiset(kQuad, kQuadIndices));
}

TEST(ImportStl, NearDuplicateCornersStayApart) {
    // (1.00000012, 1, 0) is one float ulp from (1, 1, 0): close, not identical, so not welded.
    TempDir dir;
    const std::string path = dir.write("near.stl",
                                       "solid near\n" + stlFacet({kQuad[0], kQuad[1], kQuad[2]}) +
                                           "facet normal 0 0 1\n outer loop\n  vertex 0 0 0\n"
                                           "  vertex 1.00000012 1 0\n  vertex 0 1 0\n endloop\nendfacet\n"
                                           "endsolid near\n");
    const Scene s = loadScene(path);
    expectWellFormed(s);
    EXPECT_EQ(s.triangleCount(), 2u);
    EXPECT_EQ(s.vertexCount(), 5u);
    const float nearOne = std::nextafter(1.0f, 2.0f);
    EXPECT_EQ(std::count(s.positions.begin(), s.positions.end(), glm::vec3(nearOne, 1, 0)), 1);
    EXPECT_EQ(std::count(s.positions.begin(), s.positions.end(), glm::vec3(1, 1, 0)), 1);
}

// Binary STL is read by cubeao itself (stl_binary.h), ASCII STL by OpenMesh: the same triangles
// written both ways must give the same scene, to the hash. A seeded soup with shared corners, a
// degenerate facet (two corners equal) and a header that starts with "solid" as some exporters write.
TEST(ImportStl, BinaryGivesTheSceneAsciiGives) {
    std::mt19937 rng(3);
    std::uniform_int_distribution<int> pick(0, 11);
    std::vector<glm::vec3> corners;  // a small lattice, so facets share corners
    for (int i = 0; i < 12; ++i) corners.emplace_back(float(i % 3), float(i / 3 % 2) * 0.5f, float(i / 6) * 2.0f);
    std::vector<std::array<glm::vec3, 3>> facets;
    for (int t = 0; t < 40; ++t) facets.push_back({corners[pick(rng)], corners[pick(rng)], corners[pick(rng)]});
    facets.push_back({corners[0], corners[0], corners[1]});
    facets.push_back({corners[0], corners[1], corners[4]});
    std::string ascii = "solid soup\n", binary = "solid binary soup, not ASCII";
    binary.resize(80, ' ');
    auto put32 = [&](std::uint32_t v) {
        for (int k = 0; k < 4; ++k) binary.push_back(char(v >> (8 * k) & 0xff));
    };
    put32(std::uint32_t(facets.size()));
    for (const auto& f : facets) {
        ascii += stlFacet({f[0], f[1], f[2]});
        for (int k = 0; k < 3; ++k) put32(0);  // facet normal: unused
        for (const glm::vec3& p : f)
            for (int k = 0; k < 3; ++k) {
                std::uint32_t bits;
                std::memcpy(&bits, &p[k], 4);
                put32(bits);
            }
        binary += std::string(2, '\0');
    }
    ascii += "endsolid soup\n";
    TempDir dir;
    const Scene a = loadScene(dir.write("ascii.stl", ascii)), b = loadScene(dir.write("binary.stl", binary));
    expectWellFormed(b);
    EXPECT_EQ(b.positions, a.positions);
    EXPECT_EQ(b.indices, a.indices);
    EXPECT_EQ(b.hash, a.hash);
    EXPECT_GT(a.triangleCount(), 20u);
    // A file one byte short is not binary STL by its size: it goes to OpenMesh, which refuses it.
    EXPECT_THROW(loadScene(dir.write("short.stl", binary.substr(0, binary.size() - 1))), Error);
}

TEST(ImportObj, UpperCaseExtension) {
    TempDir dir;
    const Scene s = loadScene(dir.write("QUAD.OBJ", kQuadObj));
    expectWellFormed(s);
    EXPECT_EQ(s.triangleCount(), 2u);
}

// ---- errors --------------------------------------------------------------------------------------

TEST(ImportErrors, MissingFile) {
    TempDir dir;
    const std::string path = (dir.path() / "absent.obj").string();
    const std::string msg = errorMessage([&] { loadScene(path); });
    EXPECT_TRUE(contains(msg, path)) << msg;
    EXPECT_TRUE(contains(msg, "no such file")) << msg;
}

TEST(ImportErrors, UnknownExtensionListsSupportedFormats) {
    TempDir dir;
    const std::string path = dir.write("points.xyz", "0 0 0\n1 0 0\n0 1 0\n");
    const std::string msg = errorMessage([&] { loadScene(path); });
    EXPECT_TRUE(contains(msg, path)) << msg;
    EXPECT_TRUE(contains(msg, "'.xyz'")) << msg;
    const std::vector<std::string> ext = supportedExtensions();
    for (const char* e : {".obj", ".ply", ".off", ".stl", ".ifc"})
        EXPECT_NE(std::find(ext.begin(), ext.end(), e), ext.end()) << e;
    for (const std::string& e : ext) EXPECT_TRUE(contains(msg, e)) << e << " missing from: " << msg;
    EXPECT_TRUE(contains(msg, "builtin:NAME")) << msg;
}

TEST(ImportErrors, DirectoryIsNotAScene) {
    TempDir dir;
    const fs::path sub = dir.path() / "model.obj";  // a directory with a model's name
    fs::create_directories(sub);
    for (const std::string& path : {dir.path().string(), sub.string()}) {
        const std::string msg = errorMessage([&] { loadScene(path); });
        EXPECT_TRUE(contains(msg, path)) << msg;
        EXPECT_TRUE(contains(msg, "not a regular file")) << msg;
    }
}

TEST(ImportErrors, ObjWithoutFacesHasNoTriangles) {
    TempDir dir;
    for (const std::string& text : {std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\n"), std::string("# nothing\n")}) {
        const std::string path = dir.write("empty.obj", text);
        const std::string msg = errorMessage([&] { loadScene(path); });
        EXPECT_TRUE(contains(msg, path)) << msg;
        EXPECT_TRUE(contains(msg, "no triangles")) << msg;
    }
}

TEST(ImportErrors, OnlyZeroAreaTriangles) {
    TempDir dir;
    const std::string path = dir.write("line.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
    const std::string msg = errorMessage([&] { loadScene(path); });
    EXPECT_TRUE(contains(msg, path)) << msg;
    EXPECT_TRUE(contains(msg, "zero area")) << msg;
}

TEST(ImportErrors, FaceIndexOutOfRangeIsReportedNotDropped) {
    // OpenMesh's OBJ reader passes the handle through (it does not drop the face); the soup keeps
    // it and validation reports it. Vertex 9 of the file is index 8 (0-based) of 3.
    TempDir dir;
    const std::string path = dir.write("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n");
    const std::string msg = errorMessage([&] { loadScene(path); });
    EXPECT_TRUE(contains(msg, path)) << msg;
    EXPECT_TRUE(contains(msg, "out of range")) << msg;
    EXPECT_TRUE(contains(msg, "triangle 1 refers to vertex 8 of 3")) << msg;

    // Index 0 (OBJ counts from 1) and a relative index before the first vertex end the same way.
    for (const char* face : {"f 1 2 0\n", "f 1 2 -9\n"}) {
        const std::string p = dir.write("range2.obj", std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n") + face);
        const std::string m = errorMessage([&] { loadScene(p); });
        EXPECT_TRUE(contains(m, p)) << face << ": " << m;
        EXPECT_TRUE(contains(m, "out of range")) << face << ": " << m;
    }
}

TEST(ImportErrors, OffFaceIndexOutOfRange) {
    TempDir dir;
    const std::string path = dir.write("range.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 7\n");
    const std::string msg = errorMessage([&] { loadScene(path); });
    EXPECT_TRUE(contains(msg, path)) << msg;
    EXPECT_TRUE(contains(msg, "refers to vertex 7 of 4")) << msg;
}

// Counts that lie (issue 15): a header claiming more elements than the file can hold is refused before
// the reader loops over the claim (OpenMesh adds a vertex per claimed one, stream failed or not), with
// the claim and the most the file could hold in the message. Files whose counts fit still load.
TEST(ImportErrors, HeaderCountsTheFileCannotHoldAreRefused) {
    TempDir dir;
    const std::string cube8 =
        "-0.5 -0.5 0.5\n0.5 -0.5 0.5\n-0.5 0.5 0.5\n0.5 0.5 0.5\n-0.5 0.5 -0.5\n0.5 0.5 -0.5\n-0.5 -0.5 -0.5\n"
        "0.5 -0.5 -0.5\n4 0 1 3 2\n";
    struct Case {
        const char* file;
        std::string text;
        const char* claim;
    };
    std::string stl(80, ' ');
    const std::uint32_t triangles = 1000000000u;
    stl.append(reinterpret_cast<const char*>(&triangles), 4);
    stl.append(50, '\0');
    const Case cases[] = {
        // assimp-testmodels' invalid/OutOfMemory.off, which grew `cubeao info` past 3 GB.
        {"lie.off", "OFF\n353535235358 1 0\n" + cube8, "claims 353535235358 vertex"},
        {"lie-faces.off", "OFF 8 4000000000 0\n" + cube8, "claims 4000000000 face"},
        {"lie.ply",
         "ply\nformat ascii 1.0\nelement vertex 1000000000000\nproperty float x\nproperty float y\n"
         "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n",
         "claims 1000000000000 vertex"},
        {"lie-binary.ply",
         "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
         "property float z\nelement face 90000000\nproperty list uchar int vertex_indices\nend_header\n" +
             std::string(36 + 13, '\0'),
         "claims 90000000 face"},
        {"lie.stl", stl, "claims 1000000000 triangle"},
    };
    for (const Case& c : cases) {
        const std::string path = dir.write(c.file, c.text);
        const std::string msg = errorMessage([&] { loadScene(path); });
        EXPECT_TRUE(contains(msg, path)) << msg;
        EXPECT_TRUE(contains(msg, c.claim)) << c.file << ": " << msg;
        EXPECT_TRUE(contains(msg, "can hold at most")) << msg;
    }
    // A header that ends the file (no newline after the counts) is checked too (found by fuzz_mesh).
    const std::string eof = dir.write("eof.off", "OFF 85 5842 ");
    EXPECT_TRUE(contains(errorMessage([&] { loadScene(eof); }), "claims 85 vertex elements, but the 12-byte file"));
    // The same cube with a true count loads.
    const Scene ok = loadScene(dir.write("true.off", "OFF\n8 1 0\n" + cube8));
    EXPECT_EQ(ok.triangleCount(), 2u);
}

// Found by tests/fuzz/fuzz_mesh.cpp: a PLY header with a property before any element ("element"
// misspelt) crashed OpenMesh's reader (SIGSEGV in _PLYReader_::can_u_read); refused with its line.
TEST(ImportErrors, PlyHeaderOpenMeshWouldCrashOnIsRefused) {
    TempDir dir;
    const std::string path = dir.write(
        "misspelt.ply",
        "ply\nformat ascii 1.0\neleeent vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n");
    const std::string msg = errorMessage([&] { loadScene(path); });
    EXPECT_TRUE(contains(msg, "PLY header line 3: unknown keyword \"eleeent\"")) << msg;
    const std::string orphan =
        dir.write("orphan.ply", "ply\nformat ascii 1.0\nproperty float x\nelement vertex 1\nend_header\n0\n");
    EXPECT_TRUE(contains(errorMessage([&] { loadScene(orphan); }), "line 3: a property before any element"));
}

// Found by tests/fuzz/fuzz_mesh.cpp: an OBJ face corner with no vertex index aborted the process in
// OpenMesh's reader (an assertion Debian builds keep); refused with its line.
TEST(ImportErrors, ObjFaceCornerWithoutVertexIsRefused) {
    TempDir dir;
    const std::string path = dir.write("corner.obj", "v 5 0 0\nv 1 0 0\nv 1 1 0\n f /1/1 2//1 3//1\n");
    const std::string msg = errorMessage([&] { loadScene(path); });
    EXPECT_TRUE(contains(msg, ":4: face corner '/1/1' has no vertex index")) << msg;
}

// Found by tests/fuzz/fuzz_mesh.cpp: "OFF" with no counts made OpenMesh's reader allocate without bound.
TEST(ImportErrors, OffWithoutCountsIsRefused) {
    TempDir dir;
    const std::string msg = errorMessage([&] { loadScene(dir.write("alone.off", "OFF")); });
    EXPECT_TRUE(contains(msg, "expected \"VERTICES FACES EDGES\"")) << msg;
    // "OFF 0 0" at the end of the file made OpenMesh's reader spin.
    EXPECT_TRUE(contains(errorMessage([&] { loadScene(dir.write("zero.off", "OFF  0 0 ")); }), "no vertices"));
}

// The file that showed it, as Debian ships it.
TEST(ImportErrors, AssimpOutOfMemoryOffIsRefused) {
    const fs::path path = "/usr/share/assimp/models/invalid/OutOfMemory.off";
    if (!fs::exists(path)) GTEST_SKIP() << path << " is absent (apt-get install assimp-testmodels)";
    const std::string msg = errorMessage([&] { loadScene(path.string()); });
    EXPECT_TRUE(contains(msg, "claims 353535235358 vertex elements, but the 309-byte file")) << msg;
}

// assimp's importers that crash (5.2.5: an assertion abort and a null dereference on two of the
// package's files) run in a child process: the crash is an error naming the file, and this process,
// which goes on to load a good file through assimp, lives.
TEST(ImportErrors, AnAssimpCrashIsAnErrorNamingTheFile) {
    const fs::path root = "/usr/share/assimp/models";
    if (!fs::exists(root)) GTEST_SKIP() << root << " is absent (apt-get install assimp-testmodels)";
    for (const char* file : {"OpenGEX/collada.ogex", "RAW/WithTexture.raw"}) {
        const std::string path = (root / file).string();
        const std::string msg = errorMessage([&] { loadScene(path); });
        EXPECT_TRUE(contains(msg, path + ": assimp crashed reading it (")) << msg;
    }
    const Scene ok = loadScene((root / "3DS/fels.3ds").string());
    EXPECT_GT(ok.triangleCount(), 0u);
    EXPECT_EQ(ok.positions.size(), ok.normals.size());
}

TEST(ImportErrors, NonFiniteCoordinatesNeverLoadAsNonFinite) {
    // OpenMesh's readers parse with iostreams, which reject "nan", "inf" and 1e999: the OBJ reader
    // skips the whole `v` line, the others lose track of the stream. Whatever they do, loadScene must
    // not crash and must end in either a cubeao::Error naming the file or a finite, valid scene.
    // (Found: every case below is an Error; for the OBJs the face that used the skipped vertex is
    // reported as "out of range", not as NaN.)
    TempDir dir;
    const std::vector<std::pair<std::string, std::string>> files = {
        {"nan.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv nan 0 0\nf 1 2 3\nf 1 4 3\n"},
        {"nan2.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 NaN 0\nf 1 2 3\nf 4 1 3\n"},
        {"inf.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 inf\nf 1 2 3\nf 1 4 3\n"},
        {"huge.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1e999 0 0\nf 1 2 3\nf 1 4 3\n"},
        {"nan.stl", "solid t\nfacet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n"
                    "  vertex nan 1 0\n endloop\nendfacet\nendsolid t\n"},
        {"nan.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 nan\n3 0 1 2\n"},
        {"nan.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                    "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                    "0 0 0\n1 0 0\nnan 1 0\n3 0 1 2\n"},
    };
    for (const auto& [name, text] : files) {
        SCOPED_TRACE(name);
        const std::string path = dir.write(name, text);
        try {
            const Scene s = loadScene(path);
            expectWellFormed(s);
        } catch (const Error& e) {
            EXPECT_TRUE(contains(e.what(), path)) << e.what();
        }
    }
    // The case asked about most: the NaN vertex is used by a face.
    const std::string path = dir.write("nanused.obj", files[0].second);
    const std::string msg = errorMessage([&] { loadScene(path); });
    EXPECT_TRUE(contains(msg, path)) << msg;
}

// OpenMesh's OBJ reader silently skips a `v` line it cannot parse, so every later vertex index would
// shift by one and faces would use the wrong vertices: the triangle 1-3-4 means (0,0,0) (1,0,0)
// (0,1,0), never (0,0,0) (0,1,0) (0,0,1). import.cpp scans text files for such numbers first.
TEST(ImportObj, UnparsableVertexDoesNotShiftLaterIndices) {
    TempDir dir;
    const std::string path = dir.write("shift.obj", "v 0 0 0\nv nan 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 4\n");
    try {
        const Scene s = loadScene(path);
        const std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
        EXPECT_EQ(triangleMultiset(s), triangleMultiset(p, {0, 1, 2}));
    } catch (const Error& e) {
        EXPECT_TRUE(contains(e.what(), path)) << e.what();
    }
}

// OBJ normals belong to face corners (`f v//vn`): a hard edge whose two faces share positions but not
// normals must keep each face's own normal (SoupImporter splits the vertex), not the last one written.
TEST(ImportObj, CornerNormalsOfSharedPositionsAreKept) {
    TempDir dir;
    const std::string path = dir.write("hard.obj",
                                       "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 1 0 -1\nvn 0 0 1\nvn 1 0 0\n"
                                       "f 1//1 2//1 3//1\nf 2//2 4//2 3//2\n");
    const Scene s = loadScene(path);
    expectWellFormed(s);
    ASSERT_EQ(s.triangleCount(), 2u);
    for (std::size_t t = 0; t < 2; ++t) {
        const glm::vec3 expected = s.positions[s.indices[3 * t]] == glm::vec3(0, 0, 0) ||
                                           s.positions[s.indices[3 * t + 1]] == glm::vec3(0, 0, 0) ||
                                           s.positions[s.indices[3 * t + 2]] == glm::vec3(0, 0, 0)
                                       ? glm::vec3(0, 0, 1)
                                       : glm::vec3(1, 0, 0);
        for (int k = 0; k < 3; ++k) EXPECT_EQ(s.normals[s.indices[3 * t + k]], expected) << "triangle " << t;
    }
}

// ---- builtin:NAME ------------------------------------------------------------------------------

TEST(ImportBuiltin, EveryBuiltinLoadsThroughLoadScene) {
    const std::vector<std::string> names = builtinSceneNames();
    ASSERT_EQ(names.size(), 5u);
    for (const std::string& name : names) {
        if (name == "town") continue;  // needs the shared models: test_town.cpp
        SCOPED_TRACE(name);
        const Scene s = loadScene("builtin:" + name);
        expectWellFormed(s);
        EXPECT_EQ(s.source, "builtin:" + name);
        EXPECT_FALSE(s.bounds.empty());
        EXPECT_GT(s.bounds.diagonal(), 1.0f);
        // Deterministic: loading twice gives the same geometry.
        EXPECT_EQ(loadScene("builtin:" + name).hash, s.hash);
    }
}

TEST(ImportBuiltin, UnknownNameListsTheNames) {
    const std::string msg = errorMessage([] { loadScene("builtin:nope"); });
    EXPECT_TRUE(contains(msg, "builtin:nope")) << msg;
    for (const std::string& name : builtinSceneNames()) EXPECT_TRUE(contains(msg, name)) << name << ": " << msg;
}

// ---- real scenes -------------------------------------------------------------------------------

TEST(ImportRealScene, Sibenik) {
    const fs::path path = fs::path(cubeao::test::sharedDir()) / "scenes/sibenik/sibenik.obj";
    if (!fs::exists(path)) GTEST_SKIP() << path << " is absent (see ../shared/scenes/README.md)";
    const Scene s = loadScene(path.string());
    expectWellFormed(s);
    // 80,479 faces: 494 repeat a vertex index (dropped by OpenMesh's OBJ reader), 3,338 more have
    // zero area in float (removed by repair).
    EXPECT_EQ(s.triangleCount(), 76647u);
    EXPECT_EQ(s.problems.degenerateTriangles, 3338u);
    EXPECT_FALSE(s.problems.normalsComputed);
    expectVec3Near(s.bounds.min, glm::vec3(-58.0f, -2.0f, -35.0f), 0.01f);
    expectVec3Near(s.bounds.max, glm::vec3(68.0f, 30.6f, 45.0f), 0.01f);
}

TEST(ImportRealScene, FzkHausIfc) {
    const fs::path path = "/usr/share/assimp/models/IFC/AC14-FZK-Haus.ifc";
    if (!fs::exists(path)) GTEST_SKIP() << path << " is absent (apt-get install assimp-testmodels)";
    const Scene s = loadScene(path.string());
    expectWellFormed(s);
    EXPECT_EQ(s.triangleCount(), 35903u);  // 35,906 from assimp, 3 of zero area removed
    EXPECT_EQ(s.problems.degenerateTriangles, 3u);
    EXPECT_FALSE(s.problems.warnings.empty());
    EXPECT_TRUE(s.problems.normalsComputed);
    expectVec3Near(s.bounds.min, glm::vec3(-3.0f, -1.0f, -13.0f), 0.05f);
    expectVec3Near(s.bounds.max, glm::vec3(15.0f, 6.3f, 3.0f), 0.05f);
}
