// The one header an engine includes for the cubeao run-time (docs/INTEGRATION.md; the consumer example,
// examples/consumer/main.cpp, builds from it alone): the probe cache (CacheReader), cameras
// (CameraPath, PinholeCamera, CameraView), a GL 4.5 context where the engine has none
// (gl::HeadlessContext) and the shader directory (gl::shaderDir), and the frame pipeline with the probe
// projection as its AO method (FramePipeline, ProbeProjectionPass and their settings; the residency's
// settings and statistics through ProbeProjectionSettings::residency and ProbeProjectionPass::residency()).
#pragma once

#include "cubeao/cache/cache_file.h"
#include "cubeao/core/camera.h"
#include "cubeao/gl/context.h"
#include "cubeao/gl/shader.h"
#include "cubeao/runtime/camera_view.h"
#include "cubeao/runtime/composite.h"
#include "cubeao/runtime/frame_pipeline.h"
#include "cubeao/runtime/probe_projection.h"
