#include "cubeao/scene/stl_binary.h"

#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>

#include "cubeao/core/error.h"

namespace cubeao {

namespace fs = std::filesystem;

namespace {

constexpr std::uintmax_t kHeader = 84, kTriangle = 50;

struct FileCloser {
    void operator()(std::FILE* f) const { std::fclose(f); }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

// The triangle count the header claims; false when the header cannot be read.
bool claimedTriangles(std::FILE* f, std::uint32_t& count) {
    unsigned char head[kHeader];
    if (std::fread(head, 1, kHeader, f) != kHeader) return false;
    // Little-endian by the format, whatever the machine.
    count = std::uint32_t(head[80]) | std::uint32_t(head[81]) << 8 | std::uint32_t(head[82]) << 16 |
            std::uint32_t(head[83]) << 24;
    return true;
}

float littleFloat(const unsigned char* p) {
    const std::uint32_t bits = std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 |
                               std::uint32_t(p[3]) << 24;
    float v;
    std::memcpy(&v, &bits, sizeof v);
    return v;
}

}  // namespace

bool isBinaryStl(const fs::path& path) {
    std::error_code ec;
    const std::uintmax_t size = fs::file_size(path, ec);
    if (ec || size < kHeader) return false;
    const File f(std::fopen(path.c_str(), "rb"));
    std::uint32_t count = 0;
    return f && claimedTriangles(f.get(), count) && size == kHeader + kTriangle * std::uintmax_t(count);
}

void readBinaryStl(const fs::path& path, std::vector<glm::vec3>& positions, std::vector<std::uint32_t>& indices) {
    const File f(std::fopen(path.c_str(), "rb"));
    std::uint32_t count = 0;
    if (!f || !claimedTriangles(f.get(), count)) throw Error(path.string() + ": cannot read the STL header");
    // Indices are 32-bit: three corners a triangle must stay below 2³² before repair merges them.
    if (std::uint64_t(count) * 3 > std::numeric_limits<std::uint32_t>::max())
        throw Error(path.string() + ": " + std::to_string(count) + " triangles are more than cubeao's 32-bit indices hold");
    positions.reserve(positions.size() + std::size_t(count) * 3);
    indices.reserve(indices.size() + std::size_t(count) * 3);
    constexpr std::size_t kBatch = 4096;  // triangles a read
    std::vector<unsigned char> buffer(kBatch * kTriangle);
    for (std::uint32_t done = 0; done < count;) {
        const std::size_t n = std::min<std::size_t>(kBatch, count - done);
        if (std::fread(buffer.data(), kTriangle, n, f.get()) != n)
            throw Error(path.string() + ": read error after " + std::to_string(done) + " of " + std::to_string(count) +
                        " triangles");
        for (std::size_t t = 0; t < n; ++t) {
            const unsigned char* corner = buffer.data() + t * kTriangle + 12;  // after the facet normal
            for (int k = 0; k < 3; ++k, corner += 12) {
                indices.push_back(std::uint32_t(positions.size()));
                positions.emplace_back(littleFloat(corner), littleFloat(corner + 4), littleFloat(corner + 8));
            }
        }
        done += std::uint32_t(n);
    }
}

}  // namespace cubeao
