// Atomic, durable file writes; the contract is in durable_file.h.
#include "cubeao/core/durable_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <random>
#include <utility>

#include "cubeao/core/error.h"

namespace cubeao {
namespace {

// ".TARGET.tmp-": hidden, and named after the target so a leftover is recognisable.
std::string temporaryPrefix(const std::string& target) { return "." + target + ".tmp-"; }

std::filesystem::path directoryOf(const std::filesystem::path& file) {
    return file.has_parent_path() ? file.parent_path() : std::filesystem::path(".");
}

std::string systemError() { return std::strerror(errno); }

}  // namespace

DurableFile::DurableFile(std::filesystem::path target, std::string kind)
    : target_(std::move(target)), kind_(kind.empty() ? "file" : std::move(kind)) {
    const std::filesystem::path dir = directoryOf(target_);
    std::random_device rd;
    for (int attempt = 0; attempt < 100; ++attempt) {
        path_ = dir / (temporaryPrefix(target_.filename().string()) + std::to_string(::getpid()) + "-" +
                       std::to_string(rd()));
        fd_ = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd_ >= 0) return;
        if (errno != EEXIST) break;
    }
    const std::string why = systemError();
    path_.clear();
    throw Error(target_.string() + ": cannot write " + kind_ + ": cannot create a temporary file in " + dir.string() +
                ": " + why);
}

DurableFile::DurableFile(DurableFile&& other) noexcept
    : target_(std::move(other.target_)),
      path_(std::exchange(other.path_, {})),
      kind_(std::move(other.kind_)),
      fd_(std::exchange(other.fd_, -1)),
      finished_(other.finished_),
      published_(other.published_) {}

DurableFile::~DurableFile() {
    if (fd_ >= 0) ::close(fd_);
    if (!published_ && !path_.empty()) ::unlink(path_.c_str());
}

void DurableFile::fail(const std::string& what) const {
    const std::string why = systemError();
    throw Error(target_.string() + ": cannot write " + kind_ + ": " + what + " (" + path_.filename().string() +
                "): " + why);
}

void DurableFile::write(std::span<const std::byte> bytes) {
    if (finished_) {
        errno = EBADF;
        fail("write after finish");
    }
    const std::byte* p = bytes.data();
    std::size_t n = bytes.size();
    while (n > 0) {
        const ssize_t w = ::write(fd_, p, n);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) {
            if (w == 0) errno = EIO;
            fail("write");
        }
        p += w;
        n -= std::size_t(w);
    }
}

void DurableFile::finish() {
    if (finished_) return;
    if (::fsync(fd_) != 0) fail("fsync");
    const int fd = std::exchange(fd_, -1);
    if (::close(fd) != 0) fail("close");
    finished_ = true;
}

void DurableFile::publish() {
    finish();
    if (published_) return;
    if (::rename(path_.c_str(), target_.c_str()) != 0) fail("rename");
    published_ = true;
}

void DurableFile::commit() {
    publish();
    syncDirectoryOf(target_);
}

void writeFileDurably(const std::filesystem::path& target, std::string_view bytes, const std::string& kind) {
    DurableFile file(target, kind);
    file.write(bytes);
    file.commit();
}

void syncDirectoryOf(const std::filesystem::path& file) {
    const std::filesystem::path dir = directoryOf(file);
    const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) throw Error(file.string() + ": written, but cannot open its directory to fsync: " + systemError());
    const bool failed = ::fsync(fd) != 0 && errno != EINVAL;
    const std::string why = failed ? systemError() : "";
    ::close(fd);
    if (failed) throw Error(file.string() + ": written, but fsync of its directory failed: " + why);
}

long temporaryFileWriter(const std::string& name, const std::string& target) {
    const std::string prefix = temporaryPrefix(target);
    if (name.compare(0, prefix.size(), prefix) != 0) return 0;
    const std::size_t dash = name.find('-', prefix.size());
    const std::string pid =
        name.substr(prefix.size(), dash == std::string::npos ? std::string::npos : dash - prefix.size());
    if (pid.empty() || pid.size() > 9 || pid.find_first_not_of("0123456789") != std::string::npos) return 0;
    return std::stol(pid);
}

}  // namespace cubeao
