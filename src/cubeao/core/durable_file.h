// The one way cubeao writes a file: never seen half-written, and durable once the call returns.
//
// Bytes go to a hidden temporary file beside the target, ".NAME.tmp-PID-RANDOM" (the same directory,
// so the rename stays on one file system and is atomic; named after the target, so a leftover of a
// killed writer is recognisable: temporaryFileWriter). commit() fsyncs it, renames it over the target
// and fsyncs the directory, so after a crash the target is either the old file or the whole new one.
// Destroyed without a commit (an exception, an early return), the temporary file is removed and the
// target is as it was. Every error is a cubeao::Error "TARGET: cannot write KIND: WHAT (TEMP): why".
//
// A writer that needs a path rather than bytes (an image library opening the file by name) writes
// into temporaryPath() and then calls commit(): fsync syncs the file, not the descriptor, so the
// data another open wrote is synced as well, as long as it wrote into that file rather than
// replacing it.
//
// Several files that must appear together (an export) are finished one by one and published at the
// end, then syncDirectoryOf() once; a failure before the publishing step leaves none of them.
#pragma once

#include <cstddef>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>

namespace cubeao {

class DurableFile {
public:
    // Creates the temporary file (O_EXCL, mode 0666 less the umask, as any new file). `kind` names what
    // is written in errors ("cache", "probe set"); empty: "file".
    explicit DurableFile(std::filesystem::path target, std::string kind = {});
    ~DurableFile();
    DurableFile(DurableFile&& other) noexcept;
    DurableFile& operator=(DurableFile&&) = delete;
    DurableFile(const DurableFile&) = delete;
    DurableFile& operator=(const DurableFile&) = delete;

    const std::filesystem::path& target() const { return target_; }
    const std::filesystem::path& temporaryPath() const { return path_; }

    // Appends bytes, unbuffered (a long stream buffers itself, as the cache writer does).
    void write(std::span<const std::byte> bytes);
    void write(std::string_view text) { write(std::as_bytes(std::span(text.data(), text.size()))); }

    // fsync and close the temporary file; no write after it. commit() and publish() call it if needed.
    void finish();
    // Renames the finished temporary file over the target, without syncing the directory.
    void publish();
    // finish(), publish(), syncDirectoryOf(target): the usual single-file write.
    void commit();

    // Throws the Error for a failed step `what` ("write", "fsync"), with errno's reason.
    [[noreturn]] void fail(const std::string& what) const;

private:
    std::filesystem::path target_, path_;
    std::string kind_;
    int fd_ = -1;
    bool finished_ = false, published_ = false;
};

// Writes `bytes` to `target` through a DurableFile.
void writeFileDurably(const std::filesystem::path& target, std::string_view bytes, const std::string& kind = {});

// fsync of the directory that holds `file` (a rename there is durable after it). File systems that
// cannot sync a directory (EINVAL) are let be; any other failure is an Error naming `file`.
void syncDirectoryOf(const std::filesystem::path& file);

// The process id in `name` when it is a DurableFile's temporary file for a target named `target`
// (".TARGET.tmp-PID-RANDOM"), 0 otherwise: a writer that no longer runs left it behind.
long temporaryFileWriter(const std::string& name, const std::string& target);

}  // namespace cubeao
