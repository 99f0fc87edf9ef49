#include "cubeao/scene/header_counts.h"

#include <cctype>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

namespace cubeao {
namespace {

namespace fs = std::filesystem;

// One element of a header: its claim and the fewest bytes one of it takes in the body.
struct Element {
    std::string name;
    long double count = 0;
    long double minBytes = 0;
};

// The first element whose claim, after the elements before it, cannot fit in `body` bytes.
ClaimedCounts firstImpossible(const std::vector<Element>& elements, long double body) {
    long double used = 0;
    for (const Element& e : elements) {
        if (e.minBytes <= 0) continue;
        const long double room = body > used ? body - used : 0;
        if (e.count * e.minBytes > room) return {e.name, e.count, room / e.minBytes, {}};
        used += e.count * e.minBytes;
    }
    return {};
}

// Where the body starts: the stream's position, or the file's end when the header's last line ended
// the file (getline then leaves eof set and tellg would say -1: found by tests/fuzz/fuzz_mesh.cpp,
// "OFF 85 5842" with nothing after it slipped past the size check).
std::streamoff bodyStart(std::istream& in) {
    if (in.eof()) {
        in.clear();
        in.seekg(0, std::ios::end);
    }
    return in.tellg();
}

// Reads a whole number the way a header writes it; false for anything else (left to the reader).
bool parseCount(const std::string& word, long double& out) {
    if (word.empty() || word.size() > 30) return false;
    for (char c : word)
        if (!std::isdigit(static_cast<unsigned char>(c))) return false;
    out = std::stold(word);
    return true;
}

// The body of a text OFF file: `vertices` lines of at least three numbers, then `faces` lines "K i1 .. iK"
// (colours may follow). OpenMesh's reader trusts both: a face whose K it cannot read makes it reserve
// without bound (found by tests/fuzz/fuzz_mesh.cpp), so a body that does not match is refused first.
ClaimedCounts offTextBody(std::istream& in, std::size_t vertices, std::size_t faces) {
    ClaimedCounts bad;
    std::string line;
    std::size_t seen = 0;
    const auto isNumber = [](const std::string& t, bool whole) {
        if (t.empty()) return false;
        char* end = nullptr;
        if (whole) {
            (void)std::strtoll(t.c_str(), &end, 10);
        } else {
            (void)std::strtod(t.c_str(), &end);
        }
        return end && *end == '\0' && end != t.c_str();
    };
    while (seen < vertices + faces && std::getline(in, line)) {
        std::istringstream words(line);
        std::vector<std::string> w;
        for (std::string t; words >> t;) w.push_back(t);
        if (w.empty() || w[0][0] == '#') continue;
        if (seen < vertices) {
            if (w.size() < 3 || !isNumber(w[0], false) || !isNumber(w[1], false) || !isNumber(w[2], false)) {
                bad.malformed = "OFF vertex " + std::to_string(seen) + ": expected three numbers";
                return bad;
            }
        } else {
            const long long k = isNumber(w[0], true) ? std::strtoll(w[0].c_str(), nullptr, 10) : -1;
            bool ok = k >= 1 && std::size_t(k) < w.size();
            for (long long i = 1; ok && i <= k; ++i) ok = isNumber(w[std::size_t(i)], true);
            if (!ok) {
                bad.malformed = "OFF face " + std::to_string(seen - vertices) + ": expected \"K i1 .. iK\"";
                return bad;
            }
        }
        ++seen;
    }
    if (seen < vertices + faces) {
        bad.malformed = "OFF: the header claims " + std::to_string(vertices) + " vertices and " +
                        std::to_string(faces) + " faces, the file ends after " + std::to_string(seen) + " of them";
        return bad;
    }
    return {};
}

// OFF: "[ST][C][N][4][n]OFF [BINARY]", then "vertices faces edges" (text) or three int32 (binary).
// A text vertex takes at least "0 0 0\n" (6 bytes), a face "0\n" (2); binary 12 and 4.
ClaimedCounts offClaims(std::ifstream& in, long double size) {
    std::string line;
    // Header keyword line, skipping comments and blank lines.
    while (std::getline(in, line)) {
        const auto first = line.find_first_not_of(" \t\r");
        if (first != std::string::npos && line[first] != '#') break;
    }
    ClaimedCounts bad;
    std::istringstream keywordWords(line);
    std::string keyword;
    keywordWords >> keyword;
    const std::size_t off = keyword.rfind("OFF");
    if (off == std::string::npos || off + 3 != keyword.size() ||
        keyword.substr(0, off).find_first_not_of("STCN4n") != std::string::npos) {
        bad.malformed = "OFF header: expected the keyword [ST][C][N][4][n]OFF on its first line";
        return bad;
    }
    const bool binary = line.find("BINARY") != std::string::npos;
    long double vertices = 0, faces = 0;
    if (binary) {
        std::int32_t counts[3] = {0, 0, 0};
        in.read(reinterpret_cast<char*>(counts), sizeof counts);
        if (in.gcount() != std::streamsize(sizeof counts) || counts[0] < 0 || counts[1] < 0) {
            bad.malformed = "OFF header: no vertex and face counts after the keyword";
            return bad;
        }
        vertices = counts[0], faces = counts[1];
    } else {
        // The counts may follow the keyword on its line ("OFF 8 6 0") or stand on the next one.
        std::istringstream rest(line.substr(line.find(keyword) + keyword.size()));
        std::string a, b;
        rest >> a >> b;
        if (a.empty()) {
            while (std::getline(in, line)) {
                const auto first = line.find_first_not_of(" \t\r");
                if (first != std::string::npos && line[first] != '#') break;
            }
            std::istringstream counts(line);
            counts >> a >> b;
        }
        // Without them OpenMesh's reader runs on uninitialised counts (found by tests/fuzz/fuzz_mesh.cpp:
        // "OFF" alone made it allocate without bound).
        if (!parseCount(a, vertices) || !parseCount(b, faces)) {
            bad.malformed = "OFF header: expected \"VERTICES FACES EDGES\" after the keyword";
            return bad;
        }
    }
    // No vertices or no faces is no mesh, and OpenMesh's text reader spins on such a file when the
    // counts end it ("OFF 0 0", found by tests/fuzz/fuzz_mesh.cpp).
    if (vertices == 0 || faces == 0) {
        bad.malformed = "OFF header: " + std::string(vertices == 0 ? "no vertices" : "no faces") + " (nothing to load)";
        return bad;
    }
    const std::streamoff header = bodyStart(in);
    if (header < 0) return {};
    ClaimedCounts lie = firstImpossible({{"vertex", vertices, binary ? 12.0L : 6.0L},
                                         {"face", faces, binary ? 4.0L : 2.0L}},
                                        size - (long double)header);
    if (!lie.element.empty() || binary) return lie;
    return offTextBody(in, std::size_t(vertices), std::size_t(faces));
}

int plyScalarBytes(const std::string& type) {
    static const struct {
        const char* name;
        int bytes;
    } kTypes[] = {{"char", 1},  {"uchar", 1},  {"int8", 1},  {"uint8", 1},  {"short", 2},   {"ushort", 2},
                  {"int16", 2}, {"uint16", 2}, {"int", 4},   {"uint", 4},   {"int32", 4},   {"uint32", 4},
                  {"float", 4}, {"float32", 4}, {"double", 8}, {"float64", 8}};
    for (const auto& t : kTypes)
        if (type == t.name) return t.bytes;
    return 0;
}

// PLY: "element NAME N" followed by its properties, up to "end_header". Per item an ASCII body takes at
// least two bytes a property (a digit and a separator; a list at least its count), a binary one the
// properties' sizes (a list at least its count's size). The header is checked line by line as well:
// OpenMesh's reader crashes on a property before any element and loops forever on some malformed
// headers (both found by tests/fuzz/fuzz_mesh.cpp), so only a well-formed header reaches it.
ClaimedCounts plyClaims(std::ifstream& in, long double size) {
    std::string line;
    if (!std::getline(in, line) || line.rfind("ply", 0) != 0) return {};
    bool ascii = true, haveFormat = false;
    std::vector<Element> elements;
    int lineNo = 2;
    const auto malformed = [&](const std::string& what) {
        ClaimedCounts c;
        c.malformed = "PLY header line " + std::to_string(lineNo) + ": " + what;
        return c;
    };
    constexpr int kMaxHeaderLines = 10000;
    for (; std::getline(in, line) && lineNo < kMaxHeaderLines; ++lineNo) {
        std::istringstream words(line);
        std::vector<std::string> w;
        for (std::string word; words >> word;) w.push_back(word);
        if (w.empty()) continue;
        const std::string& keyword = w[0];
        if (keyword == "comment" || keyword == "obj_info") continue;
        if (keyword == "end_header") {
            if (!haveFormat) return malformed("end_header before a format line");
            const std::streamoff header = bodyStart(in);
            if (header < 0) return {};
            return firstImpossible(elements, size - (long double)header);
        }
        if (keyword == "format") {
            if (w.size() != 3 || (w[1] != "ascii" && w[1] != "binary_little_endian" && w[1] != "binary_big_endian") ||
                w[2] != "1.0")
                return malformed("expected \"format ascii|binary_little_endian|binary_big_endian 1.0\"");
            ascii = w[1] == "ascii";
            haveFormat = true;
        } else if (keyword == "element") {
            Element e;
            if (w.size() != 3 || !parseCount(w[2], e.count)) return malformed("expected \"element NAME COUNT\"");
            e.name = w[1];
            elements.push_back(e);
        } else if (keyword == "property") {
            if (elements.empty()) return malformed("a property before any element");
            if (w.size() == 5 && w[1] == "list" && plyScalarBytes(w[2]) && plyScalarBytes(w[3]))
                elements.back().minBytes += ascii ? 2 : plyScalarBytes(w[2]);
            else if (w.size() == 3 && plyScalarBytes(w[1]))
                elements.back().minBytes += ascii ? 2 : plyScalarBytes(w[1]);
            else
                return malformed("expected \"property TYPE NAME\" or \"property list COUNT_TYPE TYPE NAME\"");
        } else {
            return malformed("unknown keyword \"" + keyword.substr(0, 40) + "\"");
        }
    }
    return malformed("no end_header");
}

// Binary STL: an 80-byte header, a uint32 triangle count, 50 bytes a triangle. ASCII STL has no count.
ClaimedCounts stlClaims(std::ifstream& in, long double size) {
    char head[84];
    in.read(head, sizeof head);
    if (in.gcount() != std::streamsize(sizeof head)) return {};
    std::string start(head, 80);
    if (start.rfind("solid", 0) == 0) {
        // "solid" opens ASCII STL, but some binary exporters write it too: ASCII has "facet" early.
        in.seekg(0);
        std::string text(512, '\0');
        in.read(text.data(), std::streamsize(text.size()));
        text.resize(std::size_t(in.gcount()));
        if (text.find("facet") != std::string::npos) return {};
    }
    std::uint32_t triangles = 0;
    std::memcpy(&triangles, head + 80, sizeof triangles);
    return firstImpossible({{"triangle", (long double)triangles, 50.0L}}, size - 84.0L);
}

}  // namespace

ClaimedCounts impossibleHeaderCount(const fs::path& path, const std::string& ext) {
    std::error_code ec;
    const auto bytes = fs::file_size(path, ec);
    if (ec) return {};
    std::ifstream in(path, std::ios::binary);
    if (!in) return {};
    const long double size = (long double)bytes;
    if (ext == ".off") return offClaims(in, size);
    if (ext == ".ply") return plyClaims(in, size);
    if (ext == ".stl") return stlClaims(in, size);
    return {};
}

}  // namespace cubeao
