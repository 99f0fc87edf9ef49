// Move-only RAII owners for GL object names, created with the GL 4.5 DSA glCreate* functions so an
// object exists (and can be labelled or filled with glNamed*) before it is ever bound.
// A handle must be destroyed while a context of its share group is current: GL names are
// meaningless without one, so the owner of the HeadlessContext must outlive every handle.
#pragma once

#include "cubeao/gl/gl.h"

#include <utility>

namespace cubeao::gl {

// Traits: `create(args...)` returns a new name, `destroy(name)` deletes it.
template <class Traits>
class Handle {
public:
    Handle() = default;  // empty: id() == 0, nothing to delete
    ~Handle() { reset(); }
    Handle(Handle&& other) noexcept : id_(std::exchange(other.id_, 0)) {}
    Handle& operator=(Handle&& other) noexcept {
        if (this != &other) {
            reset();
            id_ = std::exchange(other.id_, 0);
        }
        return *this;
    }
    Handle(const Handle&) = delete;
    Handle& operator=(const Handle&) = delete;

    // Creation is explicit so that declaring a member never touches GL (no context yet).
    template <class... Args>
    [[nodiscard]] static Handle create(Args... args) {
        return Handle(Traits::create(args...));
    }
    // Takes ownership of a name made elsewhere (e.g. by a library that hands names over).
    [[nodiscard]] static Handle adopt(GLuint id) { return Handle(id); }

    GLuint id() const { return id_; }
    explicit operator bool() const { return id_ != 0; }
    // Gives up ownership without deleting; the caller now deletes the name.
    [[nodiscard]] GLuint release() { return std::exchange(id_, 0); }
    void reset() {
        if (id_ != 0) Traits::destroy(std::exchange(id_, 0));
    }

private:
    explicit Handle(GLuint id) : id_(id) {}
    GLuint id_ = 0;
};

namespace detail {

// Most GL object kinds share the glCreateXs(n, ids) / glDeleteXs(n, ids) shape.
template <void (*Create)(GLsizei, GLuint*), void (*Delete)(GLsizei, const GLuint*)>
struct ArrayTraits {
    static GLuint create() {
        GLuint id = 0;
        Create(1, &id);
        return id;
    }
    static void destroy(GLuint id) { Delete(1, &id); }
};

// Textures and queries take their target at creation: it is fixed for the object's lifetime.
template <void (*Create)(GLenum, GLsizei, GLuint*), void (*Delete)(GLsizei, const GLuint*)>
struct TargetTraits {
    static GLuint create(GLenum target) {
        GLuint id = 0;
        Create(target, 1, &id);
        return id;
    }
    static void destroy(GLuint id) { Delete(1, &id); }
};

struct ShaderTraits {
    static GLuint create(GLenum stage) { return glCreateShader(stage); }
    static void destroy(GLuint id) { glDeleteShader(id); }
};

struct ProgramTraits {
    static GLuint create() { return glCreateProgram(); }
    static void destroy(GLuint id) { glDeleteProgram(id); }
};

}  // namespace detail

using Buffer = Handle<detail::ArrayTraits<glCreateBuffers, glDeleteBuffers>>;
using Framebuffer = Handle<detail::ArrayTraits<glCreateFramebuffers, glDeleteFramebuffers>>;
using Renderbuffer = Handle<detail::ArrayTraits<glCreateRenderbuffers, glDeleteRenderbuffers>>;
using Sampler = Handle<detail::ArrayTraits<glCreateSamplers, glDeleteSamplers>>;
using VertexArray = Handle<detail::ArrayTraits<glCreateVertexArrays, glDeleteVertexArrays>>;
using Texture = Handle<detail::TargetTraits<glCreateTextures, glDeleteTextures>>;  // create(GL_TEXTURE_2D)
using Query = Handle<detail::TargetTraits<glCreateQueries, glDeleteQueries>>;      // create(GL_TIME_ELAPSED)
using Shader = Handle<detail::ShaderTraits>;                                        // create(GL_COMPUTE_SHADER)
using Program = Handle<detail::ProgramTraits>;                                      // create()

}  // namespace cubeao::gl
