// The one include for OpenGL and EGL in cubeao. GL entry points are called directly (libOpenGL via
// GL_GLEXT_PROTOTYPES, no loader): every GL 4.5 core function is exported by GLVND on Debian 12.
#pragma once

#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES 1  // normally set by the cubeao_runtime target; here for stray includers
#endif
#ifndef EGL_NO_X11
#define EGL_NO_X11 1  // keep Xlib's macros (None, Bool, Status) out of every translation unit
#endif

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/gl.h>
#include <GL/glext.h>
