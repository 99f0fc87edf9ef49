// The GL state a pass may change and a frame relies on, saved and put back by scope.
//
// A pass run inside someone else's frame (a G-buffer draw, a stepped bake stage, the viewer's
// full-screen draw) sets its own viewport, program, framebuffers, vertex array, depth and clip
// settings; whatever it changed must look untouched to the frame around it. Before this there were
// three hand copies of the save, each saving a different subset.
#pragma once

#include "cubeao/gl/gl.h"

namespace cubeao::gl {

// Saves, at construction: the viewport, the current program, the draw and read framebuffers, the
// vertex array, the depth function, the clip control, and whether depth test, face culling and
// blending are on; puts them back at destruction. A program, framebuffer or vertex array deleted
// while saved is not bound again (its name is gone): 0 is bound instead.
class SavedState {
public:
    SavedState();
    ~SavedState();
    SavedState(const SavedState&) = delete;
    SavedState& operator=(const SavedState&) = delete;

private:
    GLint viewport_[4] = {0, 0, 0, 0};
    GLint program_ = 0, drawFramebuffer_ = 0, readFramebuffer_ = 0, vertexArray_ = 0;
    GLint depthFunc_ = GL_LESS, clipOrigin_ = GL_LOWER_LEFT, clipDepthMode_ = GL_NEGATIVE_ONE_TO_ONE;
    GLboolean depthTest_ = GL_FALSE, cull_ = GL_FALSE, blend_ = GL_FALSE;
};

}  // namespace cubeao::gl
