# ctest Install.ConsumerProject (tests/CMakeLists.txt; issue 17): the installed package works for a
# project outside the tree.
#   cmake -DBUILD=<cubeao build> -DSOURCE=<cubeao source> -DCUBEAO=<cubeao binary> -DWORK=<scratch dir>
#         -DCXX=<C++ compiler> -P tests/install_consumer.cmake
# 1. docs/INTEGRATION.md embeds examples/consumer/main.cpp verbatim (drift check), which includes one cubeao
#    header, cubeao/runtime/runtime.h;
# 2. `cmake --install BUILD --prefix WORK/prefix`; the installed headers include no third-party type
#    header they must not (CGAL, OpenImageIO, Embree, TBB, OpenMesh, assimp) and no cubeao header that
#    is not installed;
# 3. a copy of examples/consumer configures and builds against the prefix alone: no include directory
#    or definition of its compile line points into the source or build tree;
# 4. pkg-config --cflags --libs cubeao-runtime resolves, and main.cpp compiles and links with it;
# 5. a cache baked from examples/consumer/room.obj (cubeao bake --device cpu) renders: with
#    CUBEAO_SHADER_DIR unset, and again with it pointing at the installed shaders, same AO.
# 6. find_package(cubeao COMPONENTS offline): a program links cubeao::offline and cubeao::placement
#    (Embree, TBB, OpenImageIO, assimp, OpenMesh, CGAL found through the package) and makes builtin:box-room.
# Without an OpenGL 4.5 context (consumer exit code 77) the test prints "SKIPPED: " and ctest skips it.
cmake_minimum_required(VERSION 3.25)
foreach(var BUILD SOURCE CUBEAO WORK CXX)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "install_consumer.cmake: -D${var}=... missing")
  endif()
endforeach()

function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} failed (${rc}):\n${ARGN}\n${out}\n${err}")
  endif()
  set(out "${out}" PARENT_SCOPE)
endfunction()

# ---- 1. the documentation shows the example as it is
file(READ "${SOURCE}/examples/consumer/main.cpp" example)
file(READ "${SOURCE}/docs/INTEGRATION.md" doc)
set(marker "<!-- examples/consumer/main.cpp, verbatim (tests/install_consumer.cmake checks) -->\n```cpp\n")
string(FIND "${doc}" "${marker}" begin)
if(begin LESS 0)
  message(FATAL_ERROR "docs/INTEGRATION.md: no line '<!-- examples/consumer/main.cpp, verbatim ... -->' "
                      "followed by ```cpp")
endif()
string(LENGTH "${marker}" length)
math(EXPR begin "${begin} + ${length}")
string(SUBSTRING "${doc}" ${begin} -1 rest)
string(FIND "${rest}" "\n```\n" end)
math(EXPR end "${end} + 1")
string(SUBSTRING "${rest}" 0 ${end} block)
if(NOT block STREQUAL example)
  file(WRITE "${WORK}/INTEGRATION.md.cpp" "${block}")
  message(FATAL_ERROR "docs/INTEGRATION.md's code block differs from examples/consumer/main.cpp; compare\n"
                      "  ${WORK}/INTEGRATION.md.cpp\n  ${SOURCE}/examples/consumer/main.cpp")
endif()

# The example includes one cubeao header, the run-time's umbrella (issue 32: an engine needs no other).
string(REGEX MATCHALL "#include \"cubeao/[^\"]+\"" cubeaoIncludes "${example}")
if(NOT cubeaoIncludes STREQUAL "#include \"cubeao/runtime/runtime.h\"")
  message(FATAL_ERROR "examples/consumer/main.cpp includes ${cubeaoIncludes}; an engine needs only "
                      "\"cubeao/runtime/runtime.h\" (add what it lacks there)")
endif()

# ---- 2. install
file(REMOVE_RECURSE "${WORK}")
set(prefix "${WORK}/prefix")
run("cmake --install" ${CMAKE_COMMAND} --install "${BUILD}" --prefix "${prefix}")
foreach(file lib/cmake/cubeao/cubeao-config.cmake lib/pkgconfig/cubeao-runtime.pc lib/libcubeao_runtime.a
             include/cubeao/runtime/frame_pipeline.h include/cubeao/runtime/runtime.h share/cubeao/shaders/common/camera.h
             share/cubeao/shaders/runtime/project.comp)
  if(NOT EXISTS "${prefix}/${file}")
    message(FATAL_ERROR "not installed: ${prefix}/${file}")
  endif()
endforeach()
file(GLOB_RECURSE source_shaders RELATIVE "${SOURCE}/shaders" "${SOURCE}/shaders/*")
file(GLOB_RECURSE installed_shaders RELATIVE "${prefix}/share/cubeao/shaders" "${prefix}/share/cubeao/shaders/*")
if(NOT source_shaders STREQUAL installed_shaders)
  message(FATAL_ERROR "installed shaders differ from shaders/:\n${installed_shaders}\nvs\n${source_shaders}")
endif()
file(GLOB_RECURSE headers "${prefix}/include/*.h")
foreach(header IN LISTS headers)
  file(STRINGS "${header}" includes REGEX "^[ \t]*#[ \t]*include")
  foreach(line IN LISTS includes)
    if(line MATCHES "<(CGAL|OpenImageIO|OpenMesh|embree[0-9]*|tbb|oneapi|assimp)/")
      message(FATAL_ERROR "${header}: public header includes a private dependency: ${line}")
    elseif(line MATCHES "\"([^\"]+)\"" AND NOT EXISTS "${prefix}/include/${CMAKE_MATCH_1}"
           AND NOT EXISTS "${prefix}/share/cubeao/shaders/${CMAKE_MATCH_1}")
      message(FATAL_ERROR "${header}: includes \"${CMAKE_MATCH_1}\", which is not installed")
    endif()
  endforeach()
endforeach()

# ---- 3. the consumer, from a copy outside the source tree's examples/, against the prefix only
file(COPY "${SOURCE}/examples/consumer/" DESTINATION "${WORK}/consumer-src")
run("configuring the consumer" ${CMAKE_COMMAND} -S "${WORK}/consumer-src" -B "${WORK}/consumer"
    "-DCMAKE_PREFIX_PATH=${prefix}" -DCMAKE_BUILD_TYPE=Release "-DCMAKE_CXX_COMPILER=${CXX}"
    -DCMAKE_EXPORT_COMPILE_COMMANDS=ON)
run("building the consumer" ${CMAKE_COMMAND} --build "${WORK}/consumer")
file(READ "${WORK}/consumer/compile_commands.json" commands)
string(REGEX MATCHALL "(-I|-isystem |-D)[^ \"]+" flags "${commands}")
foreach(flag IN LISTS flags)
  string(REGEX REPLACE "^(-I|-isystem |-D)" "" value "${flag}")
  string(FIND "${value}" "${WORK}/" inWork)
  string(FIND "${value}" "${SOURCE}/" inSource)
  string(FIND "${value}" "${BUILD}/" inBuild)
  if(flag MATCHES "CUBEAO_SHADER_DIR" OR (NOT inWork EQUAL 0 AND (inSource EQUAL 0 OR inBuild EQUAL 0)))
    message(FATAL_ERROR "the consumer's compile line points into the cubeao tree: ${flag}\n${commands}")
  endif()
endforeach()

# ---- 4. pkg-config
set(ENV{PKG_CONFIG_PATH} "${prefix}/lib/pkgconfig")
run("pkg-config --cflags --libs cubeao-runtime" pkg-config --cflags --libs cubeao-runtime)
string(STRIP "${out}" pc)
string(REGEX MATCH "^-I([^ ]+)" _ "${pc}")
file(REAL_PATH "${CMAKE_MATCH_1}" include)  # the .pc is relocatable: ${pcfiledir}/../..
if(NOT include STREQUAL "${prefix}/include" OR NOT pc MATCHES "-lcubeao_runtime")
  message(FATAL_ERROR "pkg-config cubeao-runtime: unexpected '${pc}'")
endif()
separate_arguments(pc UNIX_COMMAND "${pc}")
run("building the consumer with pkg-config" "${CXX}" -std=c++20 -O1 "${WORK}/consumer-src/main.cpp"
    -o "${WORK}/consumer-pkgconfig" ${pc})

# ---- 5. a small cache, rendered
file(WRITE "${WORK}/probes.json"
     [[{"version":1,"probes":[{"pos":[-1,1.5,1]},{"pos":[1,1.6,-1]},{"pos":[0.7,1.5,1.2]},{"pos":[-1,1,-1.2]}]}]])
run("cubeao bake" "${CUBEAO}" bake "${WORK}/consumer-src/room.obj" --probes "${WORK}/probes.json"
    --out "${WORK}/room.cubeao" --res 32 --spp 8 --radius 0.5 --device cpu)
set(results "")
foreach(shaders "" "${prefix}/share/cubeao/shaders")
  if(shaders)
    set(env "CUBEAO_SHADER_DIR=${shaders}")
  else()
    set(env --unset=CUBEAO_SHADER_DIR)
  endif()
  execute_process(COMMAND ${CMAKE_COMMAND} -E env ${env} "${WORK}/consumer/cubeao-consumer" "${WORK}/room.cubeao"
                          "${WORK}/consumer-src/room.obj"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(rc EQUAL 77)
    message(FATAL_ERROR "SKIPPED: no OpenGL 4.5 context (headless Mesa EGL needed): ${err}")
  elseif(NOT rc EQUAL 0)
    message(FATAL_ERROR "cubeao-consumer failed (${rc}) with ${env}:\n${out}\n${err}")
  endif()
  message(STATUS "cubeao-consumer (${env}): ${out}")
  if(NOT out MATCHES "mean AO ([0-9.]+) over 160x90 pixels; 4 probes, 4 resident; uncovered ([0-9.]+);")
    message(FATAL_ERROR "cubeao-consumer: unexpected output\n${out}\n${err}")
  endif()
  set(ao ${CMAKE_MATCH_1})
  if(ao LESS 0.5 OR ao GREATER 0.99 OR CMAKE_MATCH_2 GREATER 0.05)
    message(FATAL_ERROR "cubeao-consumer: mean AO ${ao} (expected 0.5 .. 0.99), uncovered ${CMAKE_MATCH_2}")
  endif()
  list(APPEND results "${ao}")
endforeach()
list(GET results 0 fromTree)
list(GET results 1 fromPrefix)
if(NOT fromTree STREQUAL fromPrefix)
  message(FATAL_ERROR "the installed shaders give mean AO ${fromPrefix}, the default lookup ${fromTree}")
endif()

# ---- 6. the offline component
file(WRITE "${WORK}/offline-src/CMakeLists.txt" [[
cmake_minimum_required(VERSION 3.25)
project(cubeao_offline_consumer LANGUAGES CXX)
set(CMAKE_CXX_STANDARD 20)
find_package(cubeao 0.1 REQUIRED COMPONENTS offline)
add_executable(offline-consumer main.cpp)
target_link_libraries(offline-consumer PRIVATE cubeao::offline cubeao::placement)
]])
file(WRITE "${WORK}/offline-src/main.cpp" [[
#include <cstdio>

#include "cubeao/placement/placement.h"
#include "cubeao/reference/embree_scene.h"
#include "cubeao/scene/builtin.h"
#include "cubeao/scenes/builtin_scenes.h"

int main(int argc, char**) {
    cubeao::scenes::registerBuiltinScenes();
    const cubeao::Scene scene = cubeao::makeBuiltinScene("builtin:box-room");
    const cubeao::EmbreeScene embree(scene);
    if (argc > 1) cubeao::placement::PlacementScene(scene, {}, nullptr);  // linked, not run
    std::printf("builtin:box-room: %zu triangles\n", scene.triangleCount());
    return 0;
}
]])
run("configuring the offline consumer" ${CMAKE_COMMAND} -S "${WORK}/offline-src" -B "${WORK}/offline"
    "-DCMAKE_PREFIX_PATH=${prefix}" -DCMAKE_BUILD_TYPE=Release "-DCMAKE_CXX_COMPILER=${CXX}")
run("building the offline consumer" ${CMAKE_COMMAND} --build "${WORK}/offline")
run("running the offline consumer" "${WORK}/offline/offline-consumer")
if(NOT out MATCHES "builtin:box-room: [1-9][0-9]* triangles")
  message(FATAL_ERROR "offline-consumer: unexpected output '${out}'")
endif()
message(STATUS "offline-consumer: ${out}")
