// Waiting for the GPU without stalling it: a fence owner, and a ring that reads small GPU results
// (counters, per-probe feedback) back to the host a few frames late.
//
// Every host read of GPU results in cubeao goes through these two: before them the same fence and
// mapped-ring code was written by hand five times (the projection's counters, the residency's
// feedback, the stepped bake, coverage counting, live placement), each with its own flush rule and
// its own treatment of GL_WAIT_FAILED.
#pragma once

#include "cubeao/gl/handles.h"

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <utility>
#include <vector>

namespace cubeao::gl {

// A GL sync object after the commands issued so far, move-only. Empty (default) means "nothing to
// wait for": passed() is true. passed() and wait() delete the sync once it has signalled, so a fence
// seen to pass becomes empty and costs nothing to ask again.
class Fence {
public:
    Fence() = default;
    ~Fence() { reset(); }
    Fence(Fence&& other) noexcept : sync_(std::exchange(other.sync_, nullptr)) {}
    Fence& operator=(Fence&& other) noexcept {
        if (this != &other) {
            reset();
            sync_ = std::exchange(other.sync_, nullptr);
        }
        return *this;
    }
    Fence(const Fence&) = delete;
    Fence& operator=(const Fence&) = delete;

    // A fence after every command issued so far. Throws cubeao::Error when GL cannot make one.
    [[nodiscard]] static Fence insert();

    // Not yet seen to pass.
    explicit operator bool() const { return sync_ != nullptr; }
    // Whether every command before the fence has finished, without waiting (timeout 0). The poll
    // flushes the commands before it (GL_SYNC_FLUSH_COMMANDS_BIT: only while it has not passed), so a
    // fence nobody flushed still passes eventually. Throws cubeao::Error on GL_WAIT_FAILED.
    bool passed();
    // The same, waiting at most `timeout`.
    bool wait(std::chrono::nanoseconds timeout);
    // Forgets the fence (deletes the sync object without waiting).
    void reset();

private:
    GLsync sync_ = nullptr;
};

// The other direction: `regions` regions of `regionBytes` in one buffer persistently and coherently
// mapped for writing. The host fills a region, GPU commands read it (texture uploads through
// GL_PIXEL_UNPACK_BUFFER, buffer copies) and the region is fenced until they have: a region is
// written again only once its fence has passed, so the host never overwrites bytes the GPU still
// reads and never waits for it (a caller whose region is busy skips its uploads that frame).
class UploadRing {
public:
    UploadRing() = default;
    // Needs a current context; throws cubeao::Error when the buffer cannot be mapped.
    UploadRing(std::size_t regions, std::size_t regionBytes);

    // Whether region r may be written now (what was last read from it has been). Never waits.
    bool writable(std::size_t r) { return fences_.at(r).passed(); }
    // Copies `bytes` into region r at `offset` and returns their offset in buffer(), for the GL call
    // that reads them. Throws cubeao::Error past the region's end.
    std::size_t write(std::size_t r, std::size_t offset, std::span<const std::byte> bytes);
    // Fences region r after the commands issued so far (those reading it).
    void fence(std::size_t r) { fences_.at(r) = Fence::insert(); }

    std::size_t regions() const { return fences_.size(); }
    std::size_t regionBytes() const { return regionBytes_; }
    std::size_t bytes() const { return regionBytes_ * fences_.size(); }
    GLuint buffer() const { return buffer_.id(); }

private:
    Buffer buffer_;
    std::byte* mapped_ = nullptr;
    std::size_t regionBytes_ = 0;
    std::vector<Fence> fences_;
};

// The byte-level ring under ReadbackRing<T> (kept out of the template so the GL code is compiled once).
class ReadbackRingBytes {
public:
    ReadbackRingBytes() = default;
    // `slots` regions of `slotBytes` each in one buffer, persistently and coherently mapped for
    // reading. Slots start at multiples of GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT (a slot can be
    // bound as a range). Needs a current context; throws cubeao::Error when the buffer cannot be mapped.
    ReadbackRingBytes(std::size_t slots, std::size_t slotBytes);

    // Copies slotBytes bytes from `source` at `offset` into the next slot, after the commands issued
    // so far (a buffer-update barrier makes earlier shader writes to `source` visible to the copy),
    // and fences it. When every slot is still in flight the oldest is dropped unread: push never
    // waits. Returns the slot written.
    std::size_t push(GLuint source, std::size_t offset = 0);
    // The oldest slot whose copy has finished (its bytes, valid until the next push), without
    // waiting; nullopt when none is pushed or the oldest is still on the GPU.
    std::optional<std::pair<std::size_t, std::span<const std::byte>>> poll();
    // The oldest slot, waiting for its copy as long as it takes. Throws cubeao::Error when none is
    // in flight.
    std::pair<std::size_t, std::span<const std::byte>> wait();
    // Whether the oldest slot's copy has finished (poll() would return it), without taking it; false
    // when none is in flight.
    bool oldestFinished();

    std::size_t slots() const { return fences_.size(); }
    std::size_t inFlight() const { return inFlight_; }
    std::uint64_t dropped() const { return dropped_; }  // slots overwritten before anyone read them
    std::size_t bytes() const { return stride_ * fences_.size(); }  // what the buffer holds
    GLuint buffer() const { return buffer_.id(); }

private:
    std::span<const std::byte> slotBytes(std::size_t slot) const;
    std::size_t oldest() const { return (next_ + fences_.size() - inFlight_) % fences_.size(); }

    Buffer buffer_;
    const std::byte* mapped_ = nullptr;
    std::size_t slotBytes_ = 0, stride_ = 0;
    std::vector<Fence> fences_;
    std::size_t next_ = 0, inFlight_ = 0;  // the slot push writes next; slots pushed and not yet read
    std::uint64_t dropped_ = 0;
};

// A ring of `slots` read-back regions of `count` Ts each: the GPU copies a result into the next slot
// and the host takes finished slots oldest first, a frame or more later, never stalling the GPU.
// Each push carries a Tag (the frame it belongs to, a serial, a pixel count) handed back with the
// data. T must be trivially copyable: the bytes come straight from the mapping.
template <class T, class Tag = std::uint64_t>
class ReadbackRing {
public:
    struct Slot {
        Tag tag;
        std::span<const T> data;  // valid until the next push
    };

    ReadbackRing() = default;
    ReadbackRing(std::size_t slots, std::size_t count) : ring_(slots, count * sizeof(T)), tags_(slots), count_(count) {}

    // Copies count Ts from `source` at byte `offset` into the next slot, fenced; drops the oldest
    // unread slot when all are in flight (never waits).
    void push(GLuint source, const Tag& tag, std::size_t offset = 0) { tags_[ring_.push(source, offset)] = tag; }
    // The oldest finished slot, without waiting.
    std::optional<Slot> poll() {
        const auto s = ring_.poll();
        if (!s) return std::nullopt;
        return slot(*s);
    }
    // The oldest slot, waiting for it. Throws cubeao::Error when none is in flight.
    Slot wait() { return slot(ring_.wait()); }
    // Whether poll() would return a slot, without taking it.
    bool oldestFinished() { return ring_.oldestFinished(); }

    std::size_t count() const { return count_; }
    std::size_t slots() const { return ring_.slots(); }
    std::size_t inFlight() const { return ring_.inFlight(); }
    std::uint64_t dropped() const { return ring_.dropped(); }
    std::size_t bytes() const { return ring_.bytes(); }
    GLuint buffer() const { return ring_.buffer(); }

private:
    Slot slot(const std::pair<std::size_t, std::span<const std::byte>>& s) const {
        return {tags_[s.first], {reinterpret_cast<const T*>(s.second.data()), count_}};
    }

    ReadbackRingBytes ring_;
    std::vector<Tag> tags_;
    std::size_t count_ = 0;
};

}  // namespace cubeao::gl
