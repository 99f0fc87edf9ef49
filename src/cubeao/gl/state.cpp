#include "cubeao/gl/state.h"

namespace cubeao::gl {

SavedState::SavedState() {
    glGetIntegerv(GL_VIEWPORT, viewport_);
    glGetIntegerv(GL_CURRENT_PROGRAM, &program_);
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &drawFramebuffer_);
    glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &readFramebuffer_);
    glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &vertexArray_);
    glGetIntegerv(GL_DEPTH_FUNC, &depthFunc_);
    glGetIntegerv(GL_CLIP_ORIGIN, &clipOrigin_);
    glGetIntegerv(GL_CLIP_DEPTH_MODE, &clipDepthMode_);
    depthTest_ = glIsEnabled(GL_DEPTH_TEST);
    cull_ = glIsEnabled(GL_CULL_FACE);
    blend_ = glIsEnabled(GL_BLEND);
}

SavedState::~SavedState() {
    glViewport(viewport_[0], viewport_[1], viewport_[2], viewport_[3]);
    // A program, framebuffer or vertex array deleted while it was bound lives on only while bound:
    // unbound by the pass, its name is gone (binding it again is GL_INVALID_VALUE/OPERATION).
    glUseProgram(glIsProgram(GLuint(program_)) ? GLuint(program_) : 0);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, glIsFramebuffer(GLuint(drawFramebuffer_)) ? GLuint(drawFramebuffer_) : 0);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, glIsFramebuffer(GLuint(readFramebuffer_)) ? GLuint(readFramebuffer_) : 0);
    glBindVertexArray(glIsVertexArray(GLuint(vertexArray_)) ? GLuint(vertexArray_) : 0);
    glDepthFunc(GLenum(depthFunc_));
    glClipControl(GLenum(clipOrigin_), GLenum(clipDepthMode_));
    const auto enable = [](GLenum cap, GLboolean on) { on ? glEnable(cap) : glDisable(cap); };
    enable(GL_DEPTH_TEST, depthTest_);
    enable(GL_CULL_FACE, cull_);
    enable(GL_BLEND, blend_);
}

}  // namespace cubeao::gl
