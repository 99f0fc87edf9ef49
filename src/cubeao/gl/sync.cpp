#include "cubeao/gl/sync.h"

#include <algorithm>
#include <cstring>
#include <string>

#include "cubeao/core/error.h"

namespace cubeao::gl {

Fence Fence::insert() {
    Fence f;
    f.sync_ = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    if (!f.sync_) throw Error("glFenceSync failed (GL error " + std::to_string(glGetError()) + ")");
    return f;
}

bool Fence::passed() { return wait(std::chrono::nanoseconds(0)); }

bool Fence::wait(std::chrono::nanoseconds timeout) {
    if (!sync_) return true;
    const auto ns = GLuint64(std::max<std::int64_t>(timeout.count(), 0));
    const GLenum state = glClientWaitSync(sync_, GL_SYNC_FLUSH_COMMANDS_BIT, ns);
    if (state == GL_WAIT_FAILED) throw Error("glClientWaitSync failed (GL error " + std::to_string(glGetError()) + ")");
    if (state != GL_ALREADY_SIGNALED && state != GL_CONDITION_SATISFIED) return false;  // GL_TIMEOUT_EXPIRED
    reset();
    return true;
}

void Fence::reset() {
    if (sync_) glDeleteSync(std::exchange(sync_, nullptr));
}

UploadRing::UploadRing(std::size_t regions, std::size_t regionBytes)
    : regionBytes_(regionBytes), fences_(std::max<std::size_t>(regions, 1)) {
    buffer_ = Buffer::create();
    const GLbitfield flags = GL_MAP_WRITE_BIT | GL_MAP_PERSISTENT_BIT | GL_MAP_COHERENT_BIT;
    glNamedBufferStorage(buffer_.id(), GLsizeiptr(std::max<std::size_t>(bytes(), 1)), nullptr, flags);
    mapped_ = static_cast<std::byte*>(glMapNamedBufferRange(buffer_.id(), 0, GLsizeiptr(std::max<std::size_t>(bytes(), 1)), flags));
    if (!mapped_)
        throw Error("cannot map an upload ring of " + std::to_string(regions) + " × " + std::to_string(regionBytes) +
                    " bytes (GL error " + std::to_string(glGetError()) + ")");
}

std::size_t UploadRing::write(std::size_t r, std::size_t offset, std::span<const std::byte> bytes) {
    if (r >= fences_.size() || offset > regionBytes_ || bytes.size() > regionBytes_ - offset)
        throw Error("upload ring: " + std::to_string(bytes.size()) + " bytes at " + std::to_string(offset) +
                    " of region " + std::to_string(r) + " pass its end (" + std::to_string(fences_.size()) + " × " +
                    std::to_string(regionBytes_) + " bytes)");
    const std::size_t at = r * regionBytes_ + offset;
    std::memcpy(mapped_ + at, bytes.data(), bytes.size());
    return at;
}

ReadbackRingBytes::ReadbackRingBytes(std::size_t slots, std::size_t slotBytes)
    : slotBytes_(slotBytes), fences_(std::max<std::size_t>(slots, 1)) {
    GLint alignment = 4;
    glGetIntegerv(GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT, &alignment);
    const auto align = std::size_t(std::max(alignment, 4));
    stride_ = (std::max<std::size_t>(slotBytes, 1) + align - 1) / align * align;
    buffer_ = Buffer::create();
    const GLbitfield flags = GL_MAP_READ_BIT | GL_MAP_PERSISTENT_BIT | GL_MAP_COHERENT_BIT;
    glNamedBufferStorage(buffer_.id(), GLsizeiptr(bytes()), nullptr, flags);
    mapped_ = static_cast<const std::byte*>(glMapNamedBufferRange(buffer_.id(), 0, GLsizeiptr(bytes()), flags));
    if (!mapped_)
        throw Error("cannot map a read-back ring of " + std::to_string(slots) + " × " + std::to_string(slotBytes) +
                    " bytes (GL error " + std::to_string(glGetError()) + ")");
}

std::size_t ReadbackRingBytes::push(GLuint source, std::size_t offset) {
    if (inFlight_ == fences_.size()) {  // the oldest is still unread: it goes, the GPU never waits for the host
        fences_[oldest()].reset();
        --inFlight_;
        ++dropped_;
    }
    const std::size_t slot = next_;
    // Shader writes to `source` (atomics, image stores) before the copy reads it; the copy's writes
    // visible to the mapping once the fence has passed.
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glCopyNamedBufferSubData(source, buffer_.id(), GLintptr(offset), GLintptr(slot * stride_), GLsizeiptr(slotBytes_));
    glMemoryBarrier(GL_CLIENT_MAPPED_BUFFER_BARRIER_BIT);
    fences_[slot] = Fence::insert();
    next_ = (next_ + 1) % fences_.size();
    ++inFlight_;
    return slot;
}

std::optional<std::pair<std::size_t, std::span<const std::byte>>> ReadbackRingBytes::poll() {
    if (inFlight_ == 0) return std::nullopt;
    const std::size_t slot = oldest();
    if (!fences_[slot].passed()) return std::nullopt;
    --inFlight_;
    return std::pair(slot, slotBytes(slot));
}

std::pair<std::size_t, std::span<const std::byte>> ReadbackRingBytes::wait() {
    if (inFlight_ == 0) throw Error("read-back ring: nothing is in flight to wait for");
    const std::size_t slot = oldest();
    while (!fences_[slot].wait(std::chrono::seconds(1))) {
    }
    --inFlight_;
    return {slot, slotBytes(slot)};
}

bool ReadbackRingBytes::oldestFinished() { return inFlight_ > 0 && fences_[oldest()].passed(); }

std::span<const std::byte> ReadbackRingBytes::slotBytes(std::size_t slot) const {
    return {mapped_ + slot * stride_, slotBytes_};
}

}  // namespace cubeao::gl
