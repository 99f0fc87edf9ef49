// Program interface queries (GL 4.5 §7.3.1) for the layout tests: what the driver made of a shader's
// units, storage blocks and uniform blocks, to compare with the C++ mirrors in shaders/common.
#pragma once

#include <gtest/gtest.h>

#include <cstddef>
#include <initializer_list>
#include <string>

#include "cubeao/gl/gl.h"
#include "cubeao/gl/uniform_block.h"

namespace cubeao::test {

// The unit a sampler or image uniform is bound to; −1 when the program has no such active uniform.
inline GLint unitOf(GLuint program, const char* name) {
    const GLint location = glGetUniformLocation(program, name);
    if (location < 0) return -1;
    GLint unit = -1;
    glGetUniformiv(program, location, &unit);
    return unit;
}

// One property of a program resource; −1 when there is no such resource.
inline GLint resourceProperty(GLuint program, GLenum interface, const char* name, GLenum property) {
    const GLuint index = glGetProgramResourceIndex(program, interface, name);
    if (index == GL_INVALID_INDEX) return -1;
    GLint value = -1;
    glGetProgramResourceiv(program, interface, index, 1, &property, 1, nullptr, &value);
    return value;
}

inline GLint blockBinding(GLuint program, const char* block) {
    return resourceProperty(program, GL_SHADER_STORAGE_BLOCK, block, GL_BUFFER_BINDING);
}

inline GLint variableOffset(GLuint program, const char* variable) {
    return resourceProperty(program, GL_BUFFER_VARIABLE, variable, GL_OFFSET);
}

// A member of a uniform block's C++ mirror: its GLSL name and its offset in the struct.
struct BlockMember {
    const char* name;
    std::size_t offset;
};
#define CUBEAO_MEMBER(Struct, member) ::cubeao::test::BlockMember{#member, offsetof(Struct, member)}

// The std140 block `block`, declared as `uniform block { T instance; }`, is bound at `binding`, is
// as big as T and no bigger than gl::UniformBlock allocates for it, and holds each member at T's
// offset. `what` names the program in failure messages.
template <class T>
void expectUniformBlock(GLuint program, const char* block, const char* instance, GLint binding,
                        std::initializer_list<BlockMember> members, const std::string& what) {
    EXPECT_EQ(resourceProperty(program, GL_UNIFORM_BLOCK, block, GL_BUFFER_BINDING), binding) << what << ": " << block;
    const GLint size = resourceProperty(program, GL_UNIFORM_BLOCK, block, GL_BUFFER_DATA_SIZE);
    EXPECT_GE(size, GLint(sizeof(T))) << what << ": " << block;
    EXPECT_LE(size, GLint(gl::UniformBlock::kBytes<T>)) << what << ": " << block;
    for (const BlockMember& m : members) {
        const std::string name = std::string(instance) + "." + m.name;
        EXPECT_EQ(resourceProperty(program, GL_UNIFORM, name.c_str(), GL_OFFSET), GLint(m.offset))
            << what << ": " << name;
    }
}

}  // namespace cubeao::test
