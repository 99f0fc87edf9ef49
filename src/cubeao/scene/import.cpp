#include "cubeao/scene/import.h"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <assimp/DefaultLogger.hpp>
#include <assimp/Importer.hpp>
#include <assimp/LogStream.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <glm/common.hpp>
#include <spdlog/spdlog.h>

#include "cubeao/core/error.h"
#include "cubeao/scene/builtin.h"
#include "cubeao/scene/header_counts.h"
#include "cubeao/scene/stl_binary.h"
#include "cubeao/scene/repair.h"
#include "cubeao/scene/soup_importer.h"

namespace cubeao {
namespace {

namespace fs = std::filesystem;

bool contains(const std::vector<std::string>& v, const std::string& s) {
    return std::find(v.begin(), v.end(), s) != v.end();
}

const std::vector<std::string> kOpenMeshExt = {".obj", ".ply", ".off", ".stl"};

// What the installed assimp reads (issue 17): asked of the library, not a list kept here, so a newer
// assimp brings its formats with it. OBJ/PLY/OFF/STL stay with OpenMesh (double-precision OBJ/OFF, the
// header checks and the binary STL reader of this layer).
const std::vector<std::string>& assimpExtensions() {
    static const std::vector<std::string> list = [] {
        std::string joined;  // "*.3ds;*.3mf;*.ac;..."
        Assimp::Importer().GetExtensionList(joined);
        std::vector<std::string> out;
        std::size_t start = 0;
        while (start <= joined.size()) {
            std::size_t end = joined.find(';', start);
            if (end == std::string::npos) end = joined.size();
            std::string ext = joined.substr(start, end - start);
            if (ext.rfind("*", 0) == 0) ext.erase(0, 1);
            std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
            if (ext.size() > 1 && ext[0] == '.' && !contains(kOpenMeshExt, ext) && !contains(out, ext))
                out.push_back(ext);
            start = end + 1;
        }
        std::sort(out.begin(), out.end());
        return out;
    }();
    return list;
}


std::string lowerExtension(const fs::path& p) {
    std::string ext = p.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

// OpenMesh's text readers skip a number they cannot parse ("nan", "inf", "1e999") without a word: an
// OBJ `v` line vanishes and every later index shifts; the OFF and PLY readers go on with uninitialised
// values. So text files are scanned first, and a non-finite number is an error with its line.
bool isTextMesh(const fs::path& path, const std::string& ext) {
    if (ext == ".obj") return true;
    std::ifstream in(path, std::ios::binary);
    std::string head(512, '\0');
    in.read(head.data(), std::streamsize(head.size()));
    head.resize(std::size_t(in.gcount()));
    if (ext == ".ply") return head.find("format ascii") != std::string::npos;
    if (ext == ".off") return head.find("BINARY") == std::string::npos;
    return head.rfind("solid", 0) == 0 && head.find("facet") != std::string::npos;  // ASCII STL
}

// What scanTextMesh found besides problems.
struct TextScan {
    std::size_t objVertexLines = 0;  // OBJ `v` lines (0 for other formats)
    // The OBJ `v` lines' first three numbers, parsed as doubles: OpenMesh's readers parse into float
    // (9.0, every format, even a PLY `property double`), which georeferenced models cannot afford
    // (Scene::origin). Empty when a line has fewer than three numbers (the reader's error wins then).
    std::vector<glm::dvec3> objVertices;
};

// The first three whitespace-separated numbers of `words` as doubles; false when there are not three.
bool readThreeDoubles(std::istream& words, glm::dvec3& out) {
    std::string token;
    for (int k = 0; k < 3; ++k) {
        if (!(words >> token)) return false;
        char* end = nullptr;
        out[k] = std::strtod(token.c_str(), &end);
        if (end == token.c_str() || *end != '\0') return false;
    }
    return true;
}

TextScan scanTextMesh(const fs::path& path, const std::string& ext) {
    std::ifstream in(path);
    std::string line, token;
    std::size_t lineNo = 0;
    TextScan scan;
    bool objCoordinates = ext == ".obj";
    while (std::getline(in, line)) {
        ++lineNo;
        if (ext == ".obj" && line.rfind("v ", 0) == 0) {
            ++scan.objVertexLines;
            std::istringstream words(line.substr(2));
            glm::dvec3 v;
            if (objCoordinates && readThreeDoubles(words, v)) scan.objVertices.push_back(v);
            else objCoordinates = false;
        }
        // A face corner without a vertex index ("f /1/1 ...") trips an assertion in OpenMesh's OBJ
        // reader, which Debian builds with assertions on: an abort (found by tests/fuzz/fuzz_mesh.cpp).
        if (ext == ".obj") {
            std::istringstream corners(line);
            std::string keyword, corner;
            corners >> keyword;
            if (keyword == "f")
                while (corners >> corner) {
                    const std::size_t digits = corner.find_first_not_of("-+0123456789");
                    if (digits == 0 || corner.substr(0, digits).find_first_of("0123456789") == std::string::npos)
                        throw Error(path.string() + ":" + std::to_string(lineNo) + ": face corner '" + corner +
                                    "' has no vertex index");
                }
        }
        std::istringstream words(line);
        while (words >> token) {
            const char c = char(std::tolower(static_cast<unsigned char>(token[0])));
            const bool numeric = c == 'n' || c == 'i' || c == '-' || c == '+' || c == '.' ||
                                 std::isdigit(static_cast<unsigned char>(c));
            if (!numeric) continue;
            char* end = nullptr;
            const double v = std::strtod(token.c_str(), &end);
            if (end != token.c_str() && *end == '\0' && !std::isfinite(v))
                throw Error(path.string() + ":" + std::to_string(lineNo) + ": non-finite number '" + token + "'");
        }
    }
    if (!objCoordinates) scan.objVertices.clear();
    return scan;
}

// A text OFF file's vertex coordinates as doubles (see TextScan::objVertices): the first three numbers of
// each of the header's vertex count of lines after the counts, '#' comments and blank lines skipped.
// Only for the keywords whose vertex lines start with x y z ([ST][C][N]OFF); empty for anything else
// (4OFF, nOFF, BINARY) or when a line does not parse, and the reader's floats are used instead.
std::vector<glm::dvec3> offVertices(const fs::path& path) {
    std::ifstream in(path);
    std::string line;
    auto nextLine = [&](std::istringstream& words) {
        while (std::getline(in, line)) {
            line = line.substr(0, line.find('#'));
            if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
            words.clear();
            words.str(line);
            return true;
        }
        return false;
    };
    std::istringstream words;
    std::string keyword;
    if (!nextLine(words) || !(words >> keyword)) return {};
    const std::size_t off = keyword.rfind("OFF");
    if (off == std::string::npos || off + 3 != keyword.size() ||
        keyword.substr(0, off).find_first_not_of("STCN") != std::string::npos)
        return {};
    long long count = -1;
    if (!(words >> count)) {
        std::string rest;
        words.clear();
        if (words >> rest) return {};  // "OFF BINARY" and the like
        if (!nextLine(words) || !(words >> count)) return {};
    }
    if (count <= 0) return {};
    std::vector<glm::dvec3> vertices;
    for (long long i = 0; i < count; ++i) {
        glm::dvec3 v;
        if (!nextLine(words) || !readThreeDoubles(words, v)) return {};
        vertices.push_back(v);
    }
    return vertices;
}

// OpenMesh's readers (OBJ/PLY/OFF/STL) into a triangle soup. Returns whether the file carried normals.
// `filePositions` gets each position's file coordinates in double where the file is text OBJ or OFF
// (one per scene position, split corners included); it stays empty for PLY and STL, whose float
// coordinates from OpenMesh are all there is (ASCII PLY could be parsed too; not done yet).
bool readWithOpenMesh(const fs::path& path, Scene& scene, std::vector<glm::dvec3>& filePositions) {
    const std::string ext = lowerExtension(path);
    // A header that claims more elements than the file can hold would make the reader loop (and add
    // vertices) that many times: refused before it starts (header_counts.h).
    const ClaimedCounts lie = impossibleHeaderCount(path, ext);
    if (!lie.malformed.empty()) throw Error(path.string() + ": " + lie.malformed);
    if (!lie.element.empty()) {
        std::ostringstream m;
        m.precision(15);
        m << path.string() << ": the header claims " << lie.claimed << " " << lie.element << " elements, but the "
          << fs::file_size(path) << "-byte file can hold at most " << (unsigned long long)lie.mostPossible
          << " (truncated or corrupt)";
        throw Error(m.str());
    }
    filePositions.clear();
    if (ext == ".stl" && isBinaryStl(path)) {  // soups of millions of corners: see stl_binary.h
        readBinaryStl(path, scene.positions, scene.indices);
        return false;
    }
    const bool text = isTextMesh(path, ext);
    TextScan scan = text ? scanTextMesh(path, ext) : TextScan{};
    const std::size_t objVertexLines = scan.objVertexLines;
    std::vector<glm::dvec3> fileVertices = std::move(scan.objVertices);
    if (text && ext == ".off") fileVertices = offVertices(path);
    SoupImporter soup;
    OpenMesh::IO::Options opt = OpenMesh::IO::Options::VertexNormal;
    omerr().disable();  // it prints per-face chatter; failures are reported below
    const bool ok = OpenMesh::IO::IOManager().read(path.string(), soup, opt);
    omerr().enable();
    if (!ok) throw Error(path.string() + ": OpenMesh could not read the file (corrupt or not a mesh of its format)");
    if (ext == ".obj" && soup.fileVertices() != objVertexLines)
        throw Error(path.string() + ": " + std::to_string(objVertexLines - soup.fileVertices()) + " of " +
                    std::to_string(objVertexLines) +
                    " vertex lines could not be read (faces would use wrong vertices)");
    // The doubles are used only where they are the numbers the reader read: each must round to the
    // reader's float (within one float step: iostream and strtod may round a halfway case apart).
    if (!fileVertices.empty() && fileVertices.size() == soup.fileVertices()) {
        filePositions.reserve(soup.positions.size());
        for (std::size_t i = 0; i < soup.positions.size(); ++i) {
            const glm::dvec3& d = fileVertices[soup.fileVertex[i]];
            const glm::vec3& f = soup.positions[i];
            bool same = true;
            for (int k = 0; k < 3; ++k)
                same = same && std::fabs(double(float(d[k])) - double(f[k])) <=
                                   double(std::nextafter(std::fabs(f[k]), INFINITY) - std::fabs(f[k]));
            if (!same) {
                spdlog::debug("{}: vertex {} reads as {} {} {} here, {} {} {} by OpenMesh: float coordinates used",
                              path.string(), soup.fileVertex[i], d.x, d.y, d.z, f.x, f.y, f.z);
                filePositions.clear();
                break;
            }
            filePositions.push_back(d);
        }
    }
    scene.positions = std::move(soup.positions);
    scene.indices = std::move(soup.indices);
    if (soup.hasNormals) scene.normals = std::move(soup.normals);
    return soup.hasNormals;
}

// Collects assimp's warnings and errors (IFC imports produce many) into SceneProblems::warnings.
class WarningCollector : public Assimp::LogStream {
public:
    explicit WarningCollector(std::vector<std::string>& out) : out_(out) {}
    void write(const char* message) override {
        std::string m(message);
        while (!m.empty() && (m.back() == '\n' || m.back() == '\r')) m.pop_back();
        out_.push_back(std::move(m));
    }

private:
    std::vector<std::string>& out_;
};

// assimp (IFC, glTF, FBX, DXF, X3D, 3MF, ... whatever the installed assimp reads): all meshes flattened
// into world space, triangles only. Debian's assimp is built with ai_real = float, so its coordinates are
// floats already (8 mm steps at 10^5 m): re-centring (recentre below) keeps them from losing more in the
// run time's arithmetic, but cannot restore them. In this process: readWithAssimp runs it in a child.
bool readWithAssimpHere(const fs::path& path, Scene& scene) {
    std::vector<std::string> messages;
    Assimp::DefaultLogger::create("", Assimp::Logger::NORMAL, 0);
    auto* collector = new WarningCollector(messages);  // owned by the logger until detached
    Assimp::DefaultLogger::get()->attachStream(collector, Assimp::Logger::Warn | Assimp::Logger::Err);
    Assimp::Importer importer;
    importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
    const aiScene* ai = importer.ReadFile(path.string(), aiProcess_Triangulate | aiProcess_PreTransformVertices |
                                                             aiProcess_SortByPType);
    Assimp::DefaultLogger::get()->detachStream(collector, Assimp::Logger::Warn | Assimp::Logger::Err);
    delete collector;
    Assimp::DefaultLogger::kill();
    if (!ai) throw Error(path.string() + ": assimp could not import it: " + importer.GetErrorString());

    bool allNormals = ai->mNumMeshes > 0;
    for (unsigned m = 0; m < ai->mNumMeshes; ++m) allNormals = allNormals && ai->mMeshes[m]->HasNormals();
    for (unsigned m = 0; m < ai->mNumMeshes; ++m) {
        const aiMesh* mesh = ai->mMeshes[m];
        const auto base = std::uint32_t(scene.positions.size());
        for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
            const aiVector3D& p = mesh->mVertices[v];
            scene.positions.emplace_back(p.x, p.y, p.z);
            if (allNormals) scene.normals.emplace_back(mesh->mNormals[v].x, mesh->mNormals[v].y, mesh->mNormals[v].z);
        }
        for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
            const aiFace& face = mesh->mFaces[f];
            if (face.mNumIndices != 3) continue;  // points and lines: annotation, not geometry
            for (unsigned k = 0; k < 3; ++k) scene.indices.push_back(base + face.mIndices[k]);
        }
    }
    scene.problems.warnings = std::move(messages);
    return allNormals;
}

// ---- assimp in a child process ------------------------------------------------------------------
// Some of assimp's importers crash on files they should refuse (5.2.5 on assimp-testmodels:
// OpenGEX/collada.ogex aborts, RAW/WithTexture.raw dereferences null): a crash would end the whole
// command (a viewer, a bake) instead of naming the file. So the import runs in a forked child that sends
// the triangles back through a pipe; a child that dies by a signal is an error naming the file.

void writeAll(int fd, const void* data, std::size_t size) {
    const auto* p = static_cast<const char*>(data);
    while (size > 0) {
        const ssize_t n = ::write(fd, p, size);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) _exit(3);  // the parent went away: nothing to report to
        p += n;
        size -= std::size_t(n);
    }
}

template <typename T>
void writeArray(int fd, const std::vector<T>& v) {
    const std::uint64_t n = v.size();
    writeAll(fd, &n, sizeof n);
    writeAll(fd, v.data(), n * sizeof(T));
}

void writeString(int fd, const std::string& s) {
    const std::uint64_t n = s.size();
    writeAll(fd, &n, sizeof n);
    writeAll(fd, s.data(), n);
}

// Reads what the child wrote; throws when the message ends early (the child died mid-way).
class MessageReader {
public:
    MessageReader(const std::string& bytes, std::string what) : bytes_(bytes), what_(std::move(what)) {}
    template <typename T>
    T value() {
        T v;
        take(&v, sizeof v);
        return v;
    }
    template <typename T>
    std::vector<T> array() {
        const auto n = value<std::uint64_t>();
        if (n > (bytes_.size() - at_) / sizeof(T)) throw Error(what_ + ": the importer's answer is cut short");
        std::vector<T> v(n);
        take(v.data(), n * sizeof(T));
        return v;
    }
    std::string string() {
        const auto chars = array<char>();
        return std::string(chars.begin(), chars.end());
    }

private:
    void take(void* out, std::size_t n) {
        if (n > bytes_.size() - at_) throw Error(what_ + ": the importer's answer is cut short");
        if (n == 0) return;  // an empty array's data() may be null, which memcpy must not get
        std::memcpy(out, bytes_.data() + at_, n);
        at_ += n;
    }
    const std::string& bytes_;
    std::string what_;
    std::size_t at_ = 0;
};

bool readWithAssimp(const fs::path& path, Scene& scene) {
    int fds[2];
    if (::pipe(fds) != 0) throw Error(path.string() + ": cannot start the importer: " + std::strerror(errno));
    std::fflush(nullptr);  // nothing buffered is written twice
    const pid_t pid = ::fork();
    if (pid < 0) {
        ::close(fds[0]);
        ::close(fds[1]);
        throw Error(path.string() + ": cannot start the importer: " + std::strerror(errno));
    }
    if (pid == 0) {
        // The child: import, answer, _exit (no destructors or atexit handlers of the parent's state).
        ::close(fds[0]);
        try {
            Scene child;
            const bool normals = readWithAssimpHere(path, child);
            const std::uint8_t ok = 0, withNormals = normals ? 1 : 0;
            writeAll(fds[1], &ok, 1);
            writeAll(fds[1], &withNormals, 1);
            writeArray(fds[1], child.positions);
            writeArray(fds[1], child.normals);
            writeArray(fds[1], child.indices);
            const std::uint64_t warnings = child.problems.warnings.size();
            writeAll(fds[1], &warnings, sizeof warnings);
            for (const std::string& w : child.problems.warnings) writeString(fds[1], w);
        } catch (const std::exception& e) {
            const std::uint8_t failed = 1;
            writeAll(fds[1], &failed, 1);
            writeString(fds[1], e.what());
        }
        ::close(fds[1]);
        _exit(0);
    }
    ::close(fds[1]);
    std::string bytes;
    char buf[1 << 16];
    for (;;) {
        const ssize_t n = ::read(fds[0], buf, sizeof buf);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;
        bytes.append(buf, std::size_t(n));
    }
    ::close(fds[0]);
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (WIFSIGNALED(status))
        throw Error(path.string() + ": assimp crashed reading it (" + strsignal(WTERMSIG(status)) +
                    "): a damaged file, or one this assimp mishandles");
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || bytes.empty())
        throw Error(path.string() + ": the assimp importer ended without an answer (exit " +
                    std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + ")");
    MessageReader in(bytes, path.string());
    if (in.value<std::uint8_t>() != 0) throw Error(in.string());
    const bool normals = in.value<std::uint8_t>() != 0;
    scene.positions = in.array<glm::vec3>();
    scene.normals = in.array<glm::vec3>();
    scene.indices = in.array<std::uint32_t>();
    const auto warnings = in.value<std::uint64_t>();
    for (std::uint64_t w = 0; w < warnings; ++w) scene.problems.warnings.push_back(in.string());
    return normals;
}

// Moves the scene to local coordinates when chooseOrigin says it is far from the file's origin. From the
// double coordinates when the importer has them (one per position), else from the floats it read (the
// subtraction of a nearby float-exact origin is exact then, so nothing more is lost). A scene near its
// file's origin keeps the importer's floats untouched, hence today's positions and hash.
void recentre(Scene& scene, const std::vector<glm::dvec3>& filePositions) {
    const bool doubles = !filePositions.empty() && filePositions.size() == scene.positions.size();
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
    for (std::size_t i = 0; i < scene.positions.size(); ++i) {
        const glm::dvec3 p = doubles ? filePositions[i] : glm::dvec3(scene.positions[i]);
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    scene.origin = chooseOrigin(lo, hi);
    if (!scene.recentred()) return;
    for (std::size_t i = 0; i < scene.positions.size(); ++i)
        scene.positions[i] = scene.toLocal(doubles ? filePositions[i] : glm::dvec3(scene.positions[i]));
    spdlog::info("{}: far from the file's origin: re-centred on ({}, {}, {}) ({} coordinates)", scene.source,
                 scene.origin.x, scene.origin.y, scene.origin.z, doubles ? "double" : "float");
}

}  // namespace

std::vector<std::string> supportedExtensions() {
    std::vector<std::string> all = kOpenMeshExt;
    all.insert(all.end(), assimpExtensions().begin(), assimpExtensions().end());
    return all;
}

Scene loadScene(const std::string& spec) {
    if (isBuiltinSpec(spec)) return makeBuiltinScene(spec);
    const fs::path path(spec);
    std::error_code ec;
    if (!fs::exists(path, ec)) throw Error(spec + ": no such file");
    if (!fs::is_regular_file(path, ec)) throw Error(spec + ": not a regular file");
    const std::string ext = lowerExtension(path);
    Scene scene;
    scene.source = spec;
    bool hasNormals = false;
    std::vector<glm::dvec3> filePositions;
    if (contains(kOpenMeshExt, ext)) {
        hasNormals = readWithOpenMesh(path, scene, filePositions);
    } else if (contains(assimpExtensions(), ext)) {
        hasNormals = readWithAssimp(path, scene);
    } else {
        std::string list;
        for (const auto& e : supportedExtensions()) list += (list.empty() ? "" : " ") + e;
        throw Error(spec + ": unknown format '" + ext + "' (supported: " + list + ", or builtin:NAME)");
    }
    recentre(scene, filePositions);
    prepareScene(scene, hasNormals);
    spdlog::debug("{}: {} triangles, {} vertices", spec, scene.triangleCount(), scene.vertexCount());
    return scene;
}

}  // namespace cubeao
