#include "cubeao/scene/header_counts.h"

#include <cctype>
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
        if (e.count * e.minBytes > room) return {e.name, e.count, room / e.minBytes};
        used += e.count * e.minBytes;
    }
    return {};
}

// Reads a whole number the way a header writes it; false for anything else (left to the reader).
bool parseCount(const std::string& word, long double& out) {
    if (word.empty() || word.size() > 30) return false;
    for (char c : word)
        if (!std::isdigit(static_cast<unsigned char>(c))) return false;
    out = std::stold(word);
    return true;
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
    if (line.find("OFF") == std::string::npos) return {};
    const bool binary = line.find("BINARY") != std::string::npos;
    long double vertices = 0, faces = 0;
    if (binary) {
        std::int32_t counts[3] = {0, 0, 0};
        in.read(reinterpret_cast<char*>(counts), sizeof counts);
        if (in.gcount() != std::streamsize(sizeof counts) || counts[0] < 0 || counts[1] < 0) return {};
        vertices = counts[0], faces = counts[1];
    } else {
        // The counts may follow the keyword on its line ("OFF 8 6 0") or stand on the next one.
        std::istringstream rest(line.substr(line.find("OFF") + 3));
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
        if (!parseCount(a, vertices) || !parseCount(b, faces)) return {};
    }
    const std::streamoff header = in.tellg();
    if (header < 0) return {};
    return firstImpossible({{"vertex", vertices, binary ? 12.0L : 6.0L}, {"face", faces, binary ? 4.0L : 2.0L}},
                           size - (long double)header);
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
// properties' sizes (a list at least its count's size).
ClaimedCounts plyClaims(std::ifstream& in, long double size) {
    std::string line;
    if (!std::getline(in, line) || line.rfind("ply", 0) != 0) return {};
    bool ascii = true;
    std::vector<Element> elements;
    while (std::getline(in, line)) {
        std::istringstream words(line);
        std::string keyword;
        words >> keyword;
        if (keyword == "end_header") {
            const std::streamoff header = in.tellg();
            if (header < 0) return {};
            return firstImpossible(elements, size - (long double)header);
        }
        if (keyword == "format") {
            std::string format;
            words >> format;
            ascii = format == "ascii";
        } else if (keyword == "element") {
            std::string name, count;
            words >> name >> count;
            Element e;
            e.name = name;
            if (!parseCount(count, e.count)) return {};
            elements.push_back(e);
        } else if (keyword == "property" && !elements.empty()) {
            std::string type;
            words >> type;
            if (type == "list") {
                std::string countType;
                words >> countType;
                elements.back().minBytes += ascii ? 2 : plyScalarBytes(countType);
            } else {
                elements.back().minBytes += ascii ? 2 : plyScalarBytes(type);
            }
        }
    }
    return {};  // no end_header: the reader reports it
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
