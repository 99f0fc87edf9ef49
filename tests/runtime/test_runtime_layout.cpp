// The run-time passes against shaders/common/runtime_layout.h as the GL driver compiled them: work-group
// size, the unit every sampler and image is bound to, the binding of every storage block, and the
// std430 offsets, strides and sizes of the structs the C++ side writes and reads (program interface
// queries, GL 4.5 §7.3.1). A shader that hard-codes a binding, or a struct that drifts from its C++
// mirror, fails here rather than as wrong pixels.
#include <gtest/gtest.h>

#include <cstddef>
#include <string>
#include <vector>

#include "common/bake_layout.h"
#include "common/bvh.h"
#include "common/camera.h"
#include "common/placement_layout.h"
#include "common/projection.h"
#include "common/runtime_layout.h"
#include "common/viewer_layout.h"
#include "cubeao/gl/handles.h"
#include "cubeao/gl/shader.h"
#include "cubeao/gl/uniform_block.h"
#include "gl_fixture.h"
#include "gl_interface.h"

namespace {

using namespace cubeao;
using namespace cubeao::test;
namespace k = cubeao::kernel;

void expectPixelGroup(GLuint program, const std::string& name) {
    GLint size[3] = {0, 0, 0};
    glGetProgramiv(program, GL_COMPUTE_WORK_GROUP_SIZE, size);
    EXPECT_EQ(size[0], k::kPixelGroupSize) << name;
    EXPECT_EQ(size[1], k::kPixelGroupSize) << name;
    EXPECT_EQ(size[2], 1) << name;
}

// The Counters block of project.comp and ssao.glsl (pass_counters.glsl): kCounterStripes
// kernel::PassCounters at kPassCountersBuffer, the layout sumPassCounters reads.
void expectPassCounters(GLuint program, const std::string& name) {
    EXPECT_EQ(blockBinding(program, "Counters"), k::kPassCountersBuffer) << name;
    EXPECT_EQ(resourceProperty(program, GL_SHADER_STORAGE_BLOCK, "Counters", GL_BUFFER_DATA_SIZE),
              GLint(k::kPassCounterBytes))
        << name;
    EXPECT_EQ(resourceProperty(program, GL_BUFFER_VARIABLE, "counters[0].fetchesLow", GL_TOP_LEVEL_ARRAY_STRIDE),
              GLint(sizeof(k::PassCounters)))
        << name;
    EXPECT_EQ(variableOffset(program, "counters[0].fetchesLow"), GLint(offsetof(k::PassCounters, fetchesLow)))
        << name;
    EXPECT_EQ(variableOffset(program, "counters[0].fetchesHigh"), GLint(offsetof(k::PassCounters, fetchesHigh)))
        << name;
    EXPECT_EQ(variableOffset(program, "counters[0].uncovered"), GLint(offsetof(k::PassCounters, uncovered)))
        << name;
    EXPECT_EQ(variableOffset(program, "counters[0].fallbackProbe"), GLint(offsetof(k::PassCounters, fallbackProbe)))
        << name;
    EXPECT_EQ(variableOffset(program, "counters[0].geometry"), GLint(offsetof(k::PassCounters, geometry))) << name;
}

// The parameter blocks (std140) against their mirrors in shaders/common.
void expectProjectBlock(GLuint program, const std::string& name) {
    using B = k::ProjectBlock;
    expectUniformBlock<B>(program, "ProjectUniforms", "pass", k::kProjectBlock,
                          {CUBEAO_MEMBER(B, gridOrigin), CUBEAO_MEMBER(B, cellSize), CUBEAO_MEMBER(B, gridDims),
                           CUBEAO_MEMBER(B, candidatesPerCell), CUBEAO_MEMBER(B, residentOrigin),
                           CUBEAO_MEMBER(B, residentCellSize), CUBEAO_MEMBER(B, residentDims),
                           CUBEAO_MEMBER(B, residentPerCell), CUBEAO_MEMBER(B, uncoveredAo),
                           CUBEAO_MEMBER(B, cellCount)},
                          name);
    const std::size_t params = offsetof(B, params);
    using P = k::ProjectionParams;
    expectUniformBlock<B>(program, "ProjectUniforms", "pass.params", k::kProjectBlock,
                          {{"depthTolerance", params + offsetof(P, depthTolerance)},
                           {"depthSlope", params + offsetof(P, depthSlope)},
                           {"minFacing", params + offsetof(P, minFacing)},
                           {"res", params + offsetof(P, res)},
                           {"depthRes", params + offsetof(P, depthRes)},
                           {"depthOffset", params + offsetof(P, depthOffset)}},
                          name);
}

void expectCameraBlock(GLuint program, const std::string& name) {
    using B = k::CameraBlock;
    expectUniformBlock<B>(program, "CameraUniforms", "camera", k::kCameraBlock,
                          {CUBEAO_MEMBER(B, worldFromView), CUBEAO_MEMBER(B, frameSize), CUBEAO_MEMBER(B, tanHalfFovY),
                           CUBEAO_MEMBER(B, frameKey)},
                          name);
    EXPECT_EQ(resourceProperty(program, GL_UNIFORM, "camera.worldFromView", GL_MATRIX_STRIDE), 16) << name;
}

void expectSsaoBlock(GLuint program, const std::string& name) {
    using B = k::SsaoBlock;
    expectUniformBlock<B>(program, "SsaoUniforms", "ssao", k::kSsaoBlock,
                          {CUBEAO_MEMBER(B, radius), CUBEAO_MEMBER(B, falloff), CUBEAO_MEMBER(B, directions),
                           CUBEAO_MEMBER(B, steps), CUBEAO_MEMBER(B, maxRadiusPixels), CUBEAO_MEMBER(B, intensity),
                           CUBEAO_MEMBER(B, contrast), CUBEAO_MEMBER(B, bias), CUBEAO_MEMBER(B, epsilon)},
                          name);
}

TEST_F(GlTest, ProjectionShaderMatchesTheSharedLayout) {
    const gl::Program program = gl::compileComputeProgram("runtime/project.comp");
    const GLuint p = program.id();
    expectPixelGroup(p, "project");
    EXPECT_EQ(unitOf(p, "depthTex"), k::kGBufferDepthUnit);
    EXPECT_EQ(unitOf(p, "normalTex"), k::kGBufferNormalUnit);
    EXPECT_EQ(unitOf(p, "aoTex"), k::kProbeAoUnit);
    EXPECT_EQ(unitOf(p, "distanceTex"), k::kProbeDistanceUnit);
    {  // the coarse tier's samplers exist only in a residency with one (probe_projection.cpp projectDefines)
        const gl::Program tiered = gl::compileComputeProgram("runtime/project.comp", {{"PROJECT_COARSE_TIER", "1"}});
        EXPECT_EQ(unitOf(tiered.id(), "coarseAoTex"), k::kProbeCoarseAoUnit);
        EXPECT_EQ(unitOf(tiered.id(), "coarseDistanceTex"), k::kProbeCoarseDistanceUnit);
    }
    EXPECT_EQ(unitOf(p, "aoOut"), k::kAoImageUnit);
    expectPassCounters(p, "project");
    expectProjectBlock(p, "project");
    expectCameraBlock(p, "project");

    EXPECT_EQ(blockBinding(p, "ProbeTable"), k::kProbeTableBuffer);
    EXPECT_EQ(variableOffset(p, "probes[0].position"), GLint(offsetof(k::ProbeEntry, position)));
    EXPECT_EQ(variableOffset(p, "probes[0].distanceScale"), GLint(offsetof(k::ProbeEntry, distanceScale)));
    EXPECT_EQ(variableOffset(p, "probes[0].slot"), GLint(offsetof(k::ProbeEntry, slot)));
    EXPECT_EQ(variableOffset(p, "probes[0].tile"), GLint(offsetof(k::ProbeEntry, tile)));
    EXPECT_EQ(variableOffset(p, "probes[0].level"), GLint(offsetof(k::ProbeEntry, level)));
    EXPECT_EQ(variableOffset(p, "probes[0].qualityScale"), GLint(offsetof(k::ProbeEntry, qualityScale)));
    EXPECT_EQ(resourceProperty(p, GL_BUFFER_VARIABLE, "probes[0].position", GL_TOP_LEVEL_ARRAY_STRIDE),
              GLint(sizeof(k::ProbeEntry)));
    EXPECT_EQ(blockBinding(p, "Feedback"), k::kProbeFeedbackBuffer);
    EXPECT_EQ(resourceProperty(p, GL_BUFFER_VARIABLE, "demand[0]", GL_ARRAY_STRIDE), GLint(sizeof(std::uint32_t)));

    EXPECT_EQ(blockBinding(p, "Candidates"), k::kCandidateBuffer);
    EXPECT_EQ(blockBinding(p, "ResidentCandidates"), k::kResidentCandidateBuffer);
    EXPECT_EQ(blockBinding(p, "CellResidentCounts"), k::kCellResidentCountBuffer);
    EXPECT_EQ(resourceProperty(p, GL_BUFFER_VARIABLE, "candidates[0]", GL_ARRAY_STRIDE),
              GLint(sizeof(std::uint32_t)));
    // The pass that counts each cell's resident candidates reads the same table and cells.
    const gl::Program count = gl::compileComputeProgram("runtime/cell_residency.comp");
    EXPECT_EQ(blockBinding(count.id(), "ProbeTable"), k::kProbeTableBuffer);
    EXPECT_EQ(blockBinding(count.id(), "Candidates"), k::kCandidateBuffer);
    EXPECT_EQ(blockBinding(count.id(), "CellResidentCounts"), k::kCellResidentCountBuffer);
    EXPECT_EQ(variableOffset(count.id(), "probes[0].tile"), GLint(offsetof(k::ProbeEntry, tile)));
    expectProjectBlock(count.id(), "cell_residency");

    // The variant of ProbeProjectionPass::setDiagnostics writes its image at its own unit.
    const gl::Program diagnostics = gl::compileComputeProgram("runtime/project.comp", {{"PROJECT_DIAGNOSTICS", "1"}});
    EXPECT_EQ(unitOf(diagnostics.id(), "diagnosticsOut"), k::kDiagnosticsImageUnit);
    EXPECT_EQ(unitOf(diagnostics.id(), "aoOut"), k::kAoImageUnit);
    expectProjectBlock(diagnostics.id(), "project (diagnostics)");
    EXPECT_EQ(unitOf(p, "diagnosticsOut"), -1) << "the production kernel has no diagnostics";
}

// Placement's GPU coverage count (placement/src/gpu_coverage.cpp binds by placement_layout.h).
TEST_F(GlTest, CoverageCountShaderMatchesTheSharedLayout) {
    const gl::Program program = gl::compileComputeProgram("placement/coverage_count.comp");
    const GLuint p = program.id();
    expectPixelGroup(p, "coverage_count");
    EXPECT_EQ(unitOf(p, "depthTex"), k::kGBufferDepthUnit);
    EXPECT_EQ(unitOf(p, "normalTex"), k::kGBufferNormalUnit);
    EXPECT_EQ(blockBinding(p, "Probes"), k::kCoverageProbeBuffer);
    EXPECT_EQ(resourceProperty(p, GL_BUFFER_VARIABLE, "probes[0]", GL_ARRAY_STRIDE), GLint(4 * sizeof(float)));
    EXPECT_EQ(blockBinding(p, "Counters"), k::kCoverageCounterBuffer);
    EXPECT_EQ(resourceProperty(p, GL_SHADER_STORAGE_BLOCK, "Counters", GL_BUFFER_DATA_SIZE),
              GLint(sizeof(k::CoverageCounters)));
    EXPECT_EQ(variableOffset(p, "counters.pixels"), GLint(offsetof(k::CoverageCounters, pixels)));
    EXPECT_EQ(variableOffset(p, "counters.uncovered"), GLint(offsetof(k::CoverageCounters, uncovered)));
    EXPECT_EQ(blockBinding(p, "BvhNodes"), k::kBvhNodeBuffer);
    EXPECT_EQ(blockBinding(p, "BvhTriangles"), k::kBvhTriangleBuffer);

    // Its parameters: kernel::CoverageBlock, and the frame's camera.
    using B = k::CoverageBlock;
    using P = k::CoverageParams;
    expectUniformBlock<B>(p, "CoverageUniforms", "frame", k::kCoverageBlock,
                          {{"params.maxArea", offsetof(P, maxArea)},
                           {"params.maxDistance", offsetof(P, maxDistance)},
                           {"params.minFacing", offsetof(P, minFacing)},
                           {"params.res", offsetof(P, res)},
                           CUBEAO_MEMBER(B, probeCount),
                           CUBEAO_MEMBER(B, surfaceEpsilon)},
                          "coverage_count");
    expectCameraBlock(p, "coverage_count");
}

TEST_F(GlTest, ScreenSpaceShadersMatchTheSharedLayout) {
    for (const char* method : {"alchemy", "hbao", "gtao"}) {
        const std::string name = std::string("ssao/") + method + ".comp";
        const gl::Program program = gl::compileComputeProgram(name);
        const GLuint p = program.id();
        expectPixelGroup(p, name);
        EXPECT_EQ(unitOf(p, "gDepth"), k::kGBufferDepthUnit) << name;
        EXPECT_EQ(unitOf(p, "gNormal"), k::kGBufferNormalUnit) << name;
        EXPECT_EQ(unitOf(p, "aoOut"), k::kAoImageUnit) << name;
        expectPassCounters(p, name);
        expectCameraBlock(p, name);
        expectSsaoBlock(p, name);
    }
}

// The screen-space fallback's three dispatches (gtao_fill.comp; gtao_fallback.cpp binds by the layout).
TEST_F(GlTest, GtaoFallbackShadersMatchTheSharedLayout) {
    const auto compile = [](const char* pass) {
        return gl::compileComputeProgram("ssao/gtao_fill.comp", {{"GTAO_FILL_PASS", pass}});
    };
    const auto expectList = [](GLuint p, const char* block, const char* head, const char* entries,
                               const std::string& name) {
        EXPECT_EQ(resourceProperty(p, GL_BUFFER_VARIABLE, (std::string(head) + ".groupsX").c_str(), GL_OFFSET),
                  GLint(offsetof(k::FallbackList, groupsX)))
            << name << " " << block;
        EXPECT_EQ(resourceProperty(p, GL_BUFFER_VARIABLE, (std::string(head) + ".entries").c_str(), GL_OFFSET),
                  GLint(offsetof(k::FallbackList, entries)))
            << name << " " << block;
        const std::string first = std::string(entries) + "[0]";
        EXPECT_EQ(variableOffset(p, first.c_str()), GLint(sizeof(k::FallbackList))) << name << " " << block;
        EXPECT_EQ(resourceProperty(p, GL_BUFFER_VARIABLE, first.c_str(), GL_ARRAY_STRIDE),
                  GLint(sizeof(std::uint32_t)))
            << name << " " << block;
    };
    for (const char* pass : {"0", "1", "2"}) {
        const std::string name = std::string("ssao/gtao_fill.comp GTAO_FILL_PASS=") + pass;
        const gl::Program program = compile(pass);
        const GLuint p = program.id();
        expectPixelGroup(p, name);
        expectCameraBlock(p, name);
        if (blockBinding(p, "Tiles") >= 0) {  // mark, select
            EXPECT_EQ(blockBinding(p, "Tiles"), k::kFallbackTileBuffer) << name;
            EXPECT_EQ(variableOffset(p, "tiles[0].mask1"), GLint(offsetof(k::FallbackTile, mask1))) << name;
            EXPECT_EQ(resourceProperty(p, GL_BUFFER_VARIABLE, "tiles[0].mask1", GL_TOP_LEVEL_ARRAY_STRIDE),
                      GLint(sizeof(k::FallbackTile)))
                << name;
        }
        if (blockBinding(p, "TileList") >= 0) {  // mark, select
            EXPECT_EQ(blockBinding(p, "TileList"), k::kFallbackTileListBuffer) << name;
            expectList(p, "TileList", "tileList", "listedTiles", name);
        }
        if (std::string(pass) != "0") {  // select, fill
            EXPECT_EQ(blockBinding(p, "WorkList"), k::kFallbackWorkBuffer) << name;
            expectList(p, "WorkList", "workList", "workItems", name);
        }
    }
    const gl::Program mark = compile("0");
    EXPECT_EQ(unitOf(mark.id(), "aoImage"), k::kAoImageUnit);
    EXPECT_EQ(variableOffset(mark.id(), "tiles[0].mask0"), GLint(offsetof(k::FallbackTile, mask0)));
    EXPECT_EQ(variableOffset(mark.id(), "tiles[0].listed"), GLint(offsetof(k::FallbackTile, listed)));
    const gl::Program fill = compile("2");
    const GLuint p = fill.id();
    EXPECT_EQ(unitOf(p, "aoImage"), k::kAoImageUnit);
    EXPECT_EQ(unitOf(p, "gDepth"), k::kGBufferDepthUnit);
    EXPECT_EQ(unitOf(p, "gNormal"), k::kGBufferNormalUnit);
    expectSsaoBlock(p, "gtao_fill (fill)");  // the gtao baseline's settings
    EXPECT_EQ(blockBinding(p, "Counters"), k::kFallbackCountersBuffer);
    EXPECT_EQ(resourceProperty(p, GL_SHADER_STORAGE_BLOCK, "Counters", GL_BUFFER_DATA_SIZE),
              GLint(sizeof(k::FallbackCounters)));
    EXPECT_EQ(variableOffset(p, "counters.filled"), GLint(offsetof(k::FallbackCounters, filled)));
    EXPECT_EQ(variableOffset(p, "counters.blended"), GLint(offsetof(k::FallbackCounters, blended)));
    EXPECT_EQ(variableOffset(p, "counters.fetchesLow"), GLint(offsetof(k::FallbackCounters, fetchesLow)));
    EXPECT_EQ(variableOffset(p, "counters.fetchesHigh"), GLint(offsetof(k::FallbackCounters, fetchesHigh)));
}

TEST_F(GlTest, BlurAndCompositeShadersMatchTheSharedLayout) {
    for (const char* name : {"runtime/blur.comp", "runtime/composite.comp"}) {
        const gl::Program program = gl::compileComputeProgram(name);
        const GLuint p = program.id();
        expectPixelGroup(p, name);
        EXPECT_EQ(unitOf(p, "gDepth"), k::kGBufferDepthUnit) << name;
        EXPECT_EQ(unitOf(p, "gNormal"), k::kGBufferNormalUnit) << name;
        EXPECT_EQ(unitOf(p, "aoIn"), k::kAoInputUnit) << name;
    }
    const gl::Program blur = gl::compileComputeProgram("runtime/blur.comp");
    EXPECT_EQ(unitOf(blur.id(), "aoOut"), k::kAoImageUnit);
    expectCameraBlock(blur.id(), "blur");
    using Blur = k::BlurBlock;
    expectUniformBlock<Blur>(blur.id(), "BlurUniforms", "blur", k::kBlurBlock,
                             {CUBEAO_MEMBER(Blur, axis), CUBEAO_MEMBER(Blur, radius), CUBEAO_MEMBER(Blur, normalPower),
                              CUBEAO_MEMBER(Blur, depthTolerance)},
                             "blur");
    const gl::Program composite = gl::compileComputeProgram("runtime/composite.comp");
    EXPECT_EQ(unitOf(composite.id(), "shaded"), k::kShadedImageUnit);
    using Composite = k::CompositeBlock;
    expectUniformBlock<Composite>(composite.id(), "CompositeUniforms", "composite", k::kCompositeBlock,
                                  {CUBEAO_MEMBER(Composite, light), CUBEAO_MEMBER(Composite, alpha),
                                   CUBEAO_MEMBER(Composite, albedo), CUBEAO_MEMBER(Composite, ambient),
                                   CUBEAO_MEMBER(Composite, sky), CUBEAO_MEMBER(Composite, diffuse),
                                   CUBEAO_MEMBER(Composite, frameSize)},
                                  "composite");
}

// The camera G-buffer (camera_gbuffer.cpp): the triangle normals and both stages' transforms.
TEST_F(GlTest, CameraGBufferShadersMatchTheSharedLayout) {
    const gl::Program program = gl::compileRenderProgram("runtime/gbuffer.vert", "runtime/gbuffer.frag");
    EXPECT_EQ(blockBinding(program.id(), "TriangleNormals"), k::kTriangleNormalsBuffer);
    using B = k::GBufferBlock;
    expectUniformBlock<B>(program.id(), "GBufferUniforms", "transforms", k::kGBufferBlock,
                          {CUBEAO_MEMBER(B, viewFromWorld), CUBEAO_MEMBER(B, clipFromView)}, "camera G-buffer");
}

void expectBakeBlock(GLuint program, const std::string& name) {
    using B = k::BakeBlock;
    expectUniformBlock<B>(program, "BakeUniforms", "bake", k::kBakeBlock,
                          {{"clipFromWorld[0]", offsetof(B, clipFromWorld)}, CUBEAO_MEMBER(B, probe),
                           CUBEAO_MEMBER(B, res), CUBEAO_MEMBER(B, radius), CUBEAO_MEMBER(B, falloff),
                           CUBEAO_MEMBER(B, probeKey), CUBEAO_MEMBER(B, directions), CUBEAO_MEMBER(B, steps),
                           CUBEAO_MEMBER(B, spp), CUBEAO_MEMBER(B, surfaceEpsilon), CUBEAO_MEMBER(B, denoiseRadius),
                           CUBEAO_MEMBER(B, threshold)},
                          name);
    EXPECT_EQ(resourceProperty(program, GL_UNIFORM, "bake.clipFromWorld[0]", GL_ARRAY_STRIDE), GLint(sizeof(glm::mat4)))
        << name;
}

void expectEncodeBlock(GLuint program, const std::string& name) {
    using B = k::EncodeBlock;
    expectUniformBlock<B>(program, "EncodeUniforms", "encode", k::kEncodeBlock,
                          {CUBEAO_MEMBER(B, res), CUBEAO_MEMBER(B, depthRes), CUBEAO_MEMBER(B, format)}, name);
}

// The bake's passes against shaders/common/bake_layout.h as the driver compiled them: work-group
// sizes, the G-buffer's unit, every storage block's binding and the layouts gpu_bake.cpp reads and
// writes (FetchCount, TexelListHeader before the texel list, vec2 per texel, uvec4 per BC5 block).
TEST_F(GlTest, BakeShadersMatchTheSharedLayout) {
    struct Variant {
        const char* file;
        gl::ShaderDefines defines;
        int groupX, groupY;
        bool gbuffer, texelList;
    };
    const int tile = k::kBakeTileSize, list = k::kBakeListGroupSize;
    const std::vector<Variant> variants = {
        {"bake/ao_horizon.comp", {{"ESTIMATOR", "0"}}, tile, tile, true, false},
        {"bake/ao_horizon.comp", {{"ESTIMATOR", "1"}}, tile, tile, true, false},
        {"bake/ao_traced.comp", {}, list, 1, true, false},
        {"bake/ao_traced.comp", {{"TEXEL_LIST", "1"}}, list, 1, true, true},
        {"bake/ao_denoise.comp", {}, list, 1, true, false},
        {"bake/ao_denoise.comp", {{"TEXEL_LIST", "1"}}, list, 1, true, true},
        {"bake/hybrid_select.comp", {}, list, 1, true, true},
        {"bake/bc5_encode.comp", {}, tile, tile, false, false},
        {"bake/bc5_error.comp", {}, tile, tile, true, false},
        {"bake/depth_encode.comp", {{"PASS", "0"}}, tile, tile, true, false},
        {"bake/depth_encode.comp", {{"PASS", "1"}}, list, 1, false, false},
    };
    for (const Variant& v : variants) {
        std::string name = v.file;
        for (const auto& [key, value] : v.defines) name += " " + key + "=" + value;
        const gl::Program program = gl::compileComputeProgram(v.file, v.defines);
        const GLuint p = program.id();
        GLint size[3] = {0, 0, 0};
        glGetProgramiv(p, GL_COMPUTE_WORK_GROUP_SIZE, size);
        EXPECT_EQ(size[0], v.groupX) << name;
        EXPECT_EQ(size[1], v.groupY) << name;
        EXPECT_EQ(size[2], 1) << name;
        if (v.gbuffer) {
            EXPECT_EQ(unitOf(p, "gbuffer"), k::kBakeGBufferUnit) << name;
        }
        const bool encoder = name.starts_with("bake/bc5_") || name.starts_with("bake/depth_encode");
        if (encoder)
            expectEncodeBlock(p, name);
        else
            expectBakeBlock(p, name);
        if (v.texelList) {
            EXPECT_EQ(blockBinding(p, "TexelList"), k::kBakeTexelListBuffer) << name;
            EXPECT_EQ(variableOffset(p, "header.groupsX"), GLint(offsetof(k::TexelListHeader, groupsX))) << name;
            EXPECT_EQ(variableOffset(p, "header.count"), GLint(offsetof(k::TexelListHeader, count))) << name;
            EXPECT_EQ(variableOffset(p, "texels[0]"), GLint(sizeof(k::TexelListHeader))) << name;  // indirect args first
        }
    }
    const auto program = [](const char* file, gl::ShaderDefines defines = {}) {
        return gl::compileComputeProgram(file, defines);
    };
    const gl::Program horizon = program("bake/ao_horizon.comp", {{"ESTIMATOR", "0"}});
    EXPECT_EQ(blockBinding(horizon.id(), "AoOut"), k::kBakeAoBuffer);
    EXPECT_EQ(resourceProperty(horizon.id(), GL_BUFFER_VARIABLE, "aoConfidence[0]", GL_ARRAY_STRIDE), 8);  // vec2
    EXPECT_EQ(blockBinding(horizon.id(), "FetchCountBuffer"), k::kBakeFetchCountBuffer);
    EXPECT_EQ(variableOffset(horizon.id(), "counter.fetchesHigh"), GLint(offsetof(k::FetchCount, fetchesHigh)));
    const gl::Program traced = program("bake/ao_traced.comp");
    EXPECT_EQ(blockBinding(traced.id(), "AoOut"), k::kBakeAoBuffer);
    const gl::Program denoise = program("bake/ao_denoise.comp");
    EXPECT_EQ(blockBinding(denoise.id(), "AoOut"), k::kBakeAoBuffer);
    EXPECT_EQ(blockBinding(denoise.id(), "AoSource"), k::kBakeAoSourceBuffer);
    const gl::Program select = program("bake/hybrid_select.comp");
    EXPECT_EQ(blockBinding(select.id(), "AoIn"), k::kBakeAoBuffer);
    const gl::Program encode = program("bake/bc5_encode.comp");
    EXPECT_EQ(blockBinding(encode.id(), "AoIn"), k::kBakeAoBuffer);
    EXPECT_EQ(blockBinding(encode.id(), "BlocksOut"), k::kBakeBlocksBuffer);
    EXPECT_EQ(resourceProperty(encode.id(), GL_BUFFER_VARIABLE, "blocks[0]", GL_ARRAY_STRIDE), 16);  // uvec4
    const gl::Program error = program("bake/bc5_error.comp");
    EXPECT_EQ(blockBinding(error.id(), "Blocks"), k::kBakeBlocksBuffer);
    EXPECT_EQ(blockBinding(error.id(), "Partial"), k::kBakeErrorTilesBuffer);
    EXPECT_EQ(resourceProperty(error.id(), GL_BUFFER_VARIABLE, "partial[0]", GL_ARRAY_STRIDE), 8);  // vec2
    const gl::Program downsample = program("bake/depth_encode.comp", {{"PASS", "0"}});
    EXPECT_EQ(blockBinding(downsample.id(), "Coarse"), k::kBakeCoarseBuffer);
    EXPECT_EQ(blockBinding(downsample.id(), "MaxDistance"), k::kBakeMaxDistanceBuffer);
    const gl::Program pack = program("bake/depth_encode.comp", {{"PASS", "1"}});
    EXPECT_EQ(blockBinding(pack.id(), "Coarse"), k::kBakeCoarseBuffer);
    EXPECT_EQ(blockBinding(pack.id(), "Words"), k::kBakeDepthWordsBuffer);

    // The cube G-buffer, both ways gpu_bake.cpp builds it: the triangle normals at their binding.
    const gl::Program sixPass = gl::compileRenderProgram("bake/gbuffer.vert", "bake/gbuffer.frag");
    EXPECT_EQ(blockBinding(sixPass.id(), "TriangleNormals"), k::kBakeTriangleNormalsBuffer);
    expectBakeBlock(sixPass.id(), "cube G-buffer, six passes");
    const gl::Program layered = gl::buildProgram({gl::loadShaderStage(GL_VERTEX_SHADER, "bake/gbuffer.vert"),
                                                  gl::loadShaderStage(GL_GEOMETRY_SHADER, "bake/gbuffer.geom"),
                                                  gl::loadShaderStage(GL_FRAGMENT_SHADER, "bake/gbuffer.frag")},
                                                 {{"LAYERED", "1"}});
    EXPECT_EQ(blockBinding(layered.id(), "TriangleNormals"), k::kBakeTriangleNormalsBuffer);
    expectBakeBlock(layered.id(), "cube G-buffer, layered");
}

// Binding numbers are distinct per kind, so one number never means two things across the passes.
TEST(RuntimeLayout, BindingsAreDistinctPerKind) {
    const std::vector<int> units = {k::kGBufferDepthUnit,    k::kGBufferNormalUnit, k::kAoInputUnit,
                                    k::kProbeAoUnit,         k::kProbeDistanceUnit, k::kProbeCoarseAoUnit,
                                    k::kProbeCoarseDistanceUnit};
    // The placement count's buffers and the BVH's share the binding space with the run-time passes.
    // Uniform blocks are numbered apart across the run-time, placement, the bake and the viewer, whose
    // passes can share one context (live placement bakes in the viewer).
    const std::vector<int> blocks = {k::kProjectBlock, k::kCoverageBlock, k::kCameraBlock, k::kSsaoBlock,
                                     k::kBlurBlock,    k::kCompositeBlock, k::kGBufferBlock, k::kViewBlock,
                                     k::kBakeBlock,    k::kEncodeBlock};
    const std::vector<int> buffers = {k::kTriangleNormalsBuffer, k::kPassCountersBuffer, k::kProbeTableBuffer,
                                      k::kCandidateBuffer,       k::kResidentCandidateBuffer, k::kCoverageProbeBuffer, k::kCoverageCounterBuffer,
                                      k::kFallbackTileBuffer,    k::kFallbackCountersBuffer, k::kFallbackTileListBuffer,
                                      k::kFallbackWorkBuffer,    k::kProbeFeedbackBuffer,   k::kCellResidentCountBuffer,
                                      int(k::kBvhNodeBuffer),    int(k::kBvhTriangleBuffer)};
    for (const auto* list : {&units, &blocks, &buffers})
        for (std::size_t i = 0; i < list->size(); ++i)
            for (std::size_t j = i + 1; j < list->size(); ++j) EXPECT_NE((*list)[i], (*list)[j]) << i << " vs " << j;
    EXPECT_NE(k::kAoImageUnit, k::kShadedImageUnit);
    EXPECT_NE(k::kAoImageUnit, k::kDiagnosticsImageUnit);
    EXPECT_NE(k::kShadedImageUnit, k::kDiagnosticsImageUnit);
    EXPECT_EQ(k::pixelGroups(1), 1u);
    EXPECT_EQ(k::pixelGroups(k::kPixelGroupSize), 1u);
    EXPECT_EQ(k::pixelGroups(k::kPixelGroupSize + 1), 2u);
}

}  // namespace
