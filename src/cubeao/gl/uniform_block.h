// A std140 uniform block's buffer, filled from its C++ mirror: the way kernel parameters reach a
// shader. The mirror is a struct of shaders/common read by the GLSL block and the C++ side alike,
// with static_asserts on its offsets beside it and a driver check of the same offsets
// (tests/runtime/test_runtime_layout.cpp), so a member that drifts fails at build or test time instead of
// setting the wrong uniform; no name is looked up.
#pragma once

#include "cubeao/gl/handles.h"

#include <cstddef>
#include <type_traits>

namespace cubeao::gl {

class UniformBlock {
public:
    // std140 rounds a block holding a struct up to 16 bytes; the buffer holds at least that.
    template <class T>
    static constexpr std::size_t kBytes = (sizeof(T) + 15) / 16 * 16;

    UniformBlock() = default;  // empty: no buffer yet
    // A buffer for T holding `value` (needs a current context).
    template <class T>
    [[nodiscard]] static UniformBlock create(const T& value) {
        UniformBlock b;
        b.buffer_ = Buffer::create();
        b.bytes_ = kBytes<T>;
        glNamedBufferStorage(b.buffer_.id(), GLsizeiptr(b.bytes_), nullptr, GL_DYNAMIC_STORAGE_BIT);
        b.set(value);
        return b;
    }
    // New contents, in order with the commands around it (dispatches issued before read the old ones).
    template <class T>
    void set(const T& value) {
        static_assert(std::is_trivially_copyable_v<T>, "a uniform block's mirror is copied as bytes");
        glNamedBufferSubData(buffer_.id(), 0, GLsizeiptr(sizeof(T)), &value);
    }
    void bind(GLuint binding) const { glBindBufferBase(GL_UNIFORM_BUFFER, binding, buffer_.id()); }
    // A pass's per-frame block: created on first use, else set, then bound at `binding`.
    template <class T>
    void upload(const T& value, GLuint binding) {
        if (buffer_.id() == 0)
            *this = create(value);
        else
            set(value);
        bind(binding);
    }
    GLuint id() const { return buffer_.id(); }
    std::size_t bytes() const { return bytes_; }

private:
    Buffer buffer_;
    std::size_t bytes_ = 0;
};

}  // namespace cubeao::gl
