# cubeao_check_headers: compile every header of a library alone, against only that library's declared
# dependencies, so an include of a higher layer (or of a dependency the library does not declare)
# fails the build (issue 11, DESIGN.md §2).
#
#   cubeao_check_headers(<target>
#     [DIRS "<root>:<subdir>" ...]     headers <root>/<subdir>/*.h, included as "<subdir>/NAME.h"
#     [HEADERS "<root>:<subdir>/NAME.h" ...]   single headers (a library that owns one file of a directory)
#     [EXCLUDE NAME.h ...]             headers of DIRS that belong to another library
#     [PRIVATE_HEADERS NAME.h ...])    headers of DIRS used only by the library's own sources: checked
#                                      with its PRIVATE dependencies too
#
# Why not just compile with the target's include directories: every library shares `src`, so a runtime
# header that includes "cubeao/scene/x.h" would still find it. Instead each check gets an include
# directory of its own, <build>/header_check/<target>/include, holding symbolic links to exactly the
# header directories of <target> and of the cubeao libraries in its INTERFACE_LINK_LIBRARIES closure
# (private dependencies, $<LINK_ONLY:...>, excluded). Third-party targets in that closure are linked
# for their usage requirements, cubeao targets contribute only their compile definitions. Each header
# is included twice from a generated .cpp (the second include checks #pragma once), and all of a
# target's .cpp files form one OBJECT library, <target>_header_check, built by default (ALL).
#
# The work runs deferred, at the end of the top-level CMakeLists.txt, so link libraries added after
# the call and dependencies declared in any order are all seen.

set(_cubeao_header_check_dir "${CMAKE_CURRENT_LIST_DIR}")

# A target property as a list: empty, not "<var>-NOTFOUND", when the target has none.
function(_cubeao_target_list out target property)
  get_target_property(value ${target} ${property})
  if(NOT value)
    set(value "")
  endif()
  set(${out} "${value}" PARENT_SCOPE)
endfunction()

function(cubeao_check_headers target)
  cmake_parse_arguments(arg "" "" "DIRS;HEADERS;EXCLUDE;PRIVATE_HEADERS" ${ARGN})
  if(NOT TARGET ${target})
    message(FATAL_ERROR "cubeao_check_headers: no target ${target}")
  endif()
  set(dirs "")
  foreach(entry IN LISTS arg_DIRS)
    list(APPEND dirs "${entry}")
  endforeach()
  foreach(entry IN LISTS arg_HEADERS)
    if(NOT entry MATCHES "^(.*):(.*)/([^/]+)$")
      message(FATAL_ERROR "cubeao_check_headers(${target}): HEADERS entry '${entry}' is not ROOT:SUBDIR/NAME.h")
    endif()
    list(APPEND dirs "${CMAKE_MATCH_1}:${CMAKE_MATCH_2}")
  endforeach()
  set_property(TARGET ${target} PROPERTY CUBEAO_HEADER_DIRS "${dirs}")
  cmake_language(EVAL CODE "
    cmake_language(DEFER DIRECTORY [[${CMAKE_SOURCE_DIR}]] CALL _cubeao_check_headers_now [[${target}]]
      [[${arg_DIRS}]] [[${arg_HEADERS}]] [[${arg_EXCLUDE}]] [[${arg_PRIVATE_HEADERS}]])")
endfunction()

# Walks `links` (a link-library list): cubeao libraries (targets with CUBEAO_HEADER_DIRS) recursively
# through their INTERFACE_LINK_LIBRARIES, appending their header dirs to ${outDirs} and compile
# definitions to ${outDefs}; everything else (third-party) to ${outLibs}.
function(_cubeao_header_closure links outDirs outLibs outDefs)
  set(dirs "")
  set(libs "")
  set(defs "")
  set(seen "")
  set(queue ${links})
  while(queue)
    list(POP_FRONT queue item)
    if(item MATCHES "^\\$<LINK_ONLY:" OR item IN_LIST seen)
      continue()
    endif()
    list(APPEND seen "${item}")
    if(TARGET ${item})
      get_target_property(aliased ${item} ALIASED_TARGET)
      if(aliased)
        set(item ${aliased})
      endif()
      get_target_property(itemDirs ${item} CUBEAO_HEADER_DIRS)
      if(itemDirs)
        list(APPEND dirs ${itemDirs})
        get_target_property(itemDefs ${item} INTERFACE_COMPILE_DEFINITIONS)
        if(itemDefs)
          list(APPEND defs ${itemDefs})
        endif()
        get_target_property(itemLinks ${item} INTERFACE_LINK_LIBRARIES)
        if(itemLinks)
          list(APPEND queue ${itemLinks})
        endif()
        continue()
      elseif(item MATCHES "^cubeao_")
        message(FATAL_ERROR "cubeao_check_headers: ${item} is a dependency but has no cubeao_check_headers() call")
      endif()
    endif()
    list(APPEND libs "${item}")
  endwhile()
  list(REMOVE_DUPLICATES dirs)
  list(REMOVE_DUPLICATES defs)
  set(${outDirs} "${dirs}" PARENT_SCOPE)
  set(${outLibs} "${libs}" PARENT_SCOPE)
  set(${outDefs} "${defs}" PARENT_SCOPE)
endfunction()

# Links <build>/header_check/<name>/include/<subdir> to <root>/<subdir> for each "<root>:<subdir>" of
# `dirs`; sets ${outInclude} to that include directory.
function(_cubeao_stage_headers name dirs outInclude)
  set(include "${CMAKE_BINARY_DIR}/header_check/${name}/include")
  list(FILTER dirs EXCLUDE REGEX "^$")
  list(REMOVE_DUPLICATES dirs)
  foreach(entry IN LISTS dirs)
    string(REGEX MATCH "^(.*):([^:]*)$" _ "${entry}")
    set(root "${CMAKE_MATCH_1}")
    set(subdir "${CMAKE_MATCH_2}")
    set(link "${include}/${subdir}")
    get_filename_component(parent "${link}" DIRECTORY)
    file(MAKE_DIRECTORY "${parent}")
    if(IS_SYMLINK "${link}")
      file(READ_SYMLINK "${link}" old)
      if(NOT old STREQUAL "${root}/${subdir}")
        file(REMOVE "${link}")
      endif()
    endif()
    if(NOT IS_SYMLINK "${link}")
      file(CREATE_LINK "${root}/${subdir}" "${link}" SYMBOLIC)
    endif()
  endforeach()
  set(${outInclude} "${include}" PARENT_SCOPE)
endfunction()

# One OBJECT library that compiles each of `headers` ("SUBDIR/NAME.h" under the staged include dir)
# alone, with the header dirs `dirs` staged as links and `libs`, `defs` as usage requirements.
function(_cubeao_header_check_library name headers dirs libs defs)
  set(base "${CMAKE_BINARY_DIR}/header_check/${name}")
  list(FILTER defs EXCLUDE REGEX "^$")
  _cubeao_stage_headers(${name} "${dirs}" include)
  set(sources "")
  foreach(header IN LISTS headers)
    string(MAKE_C_IDENTIFIER "${header}" id)
    set(cpp "${base}/${id}.cpp")
    file(CONFIGURE OUTPUT "${cpp}" CONTENT
"// Generated by cmake/HeaderCheck.cmake: \"${header}\" must compile alone, and twice (#pragma once).
#include \"${header}\"
#include \"${header}\"
" @ONLY)
    list(APPEND sources "${cpp}")
  endforeach()
  add_library(${name} OBJECT ${sources})
  target_include_directories(${name} PRIVATE "${include}")
  target_link_libraries(${name} PRIVATE ${libs})
  target_compile_definitions(${name} PRIVATE ${defs})
endfunction()

function(_cubeao_check_headers_now target dirs headers exclude privateHeaders)
  # The headers to check: every *.h of each DIRS entry (re-globbed when files come or go), minus
  # EXCLUDE, plus HEADERS; split into public and private.
  set(public "")
  set(private "")
  foreach(entry IN LISTS dirs)
    string(REGEX MATCH "^(.*):([^:]*)$" _ "${entry}")
    set(root "${CMAKE_MATCH_1}")
    set(subdir "${CMAKE_MATCH_2}")
    file(GLOB found CONFIGURE_DEPENDS RELATIVE "${root}/${subdir}" "${root}/${subdir}/*.h")
    list(SORT found)
    foreach(name IN LISTS found)
      if(name IN_LIST exclude)
        continue()
      elseif(name IN_LIST privateHeaders)
        list(APPEND private "${subdir}/${name}")
      else()
        list(APPEND public "${subdir}/${name}")
      endif()
    endforeach()
  endforeach()
  foreach(entry IN LISTS headers)
    string(REGEX MATCH "^(.*):(.*)$" _ "${entry}")
    list(APPEND public "${CMAKE_MATCH_2}")
  endforeach()

  get_target_property(ownDirs ${target} CUBEAO_HEADER_DIRS)
  _cubeao_target_list(ownDefs ${target} INTERFACE_COMPILE_DEFINITIONS)
  _cubeao_target_list(interfaceLinks ${target} INTERFACE_LINK_LIBRARIES)
  _cubeao_target_list(allLinks ${target} LINK_LIBRARIES)
  _cubeao_header_closure("${interfaceLinks}" depDirs libs defs)
  if(public)
    _cubeao_header_check_library(${target}_header_check "${public}" "${ownDirs};${depDirs}" "${libs}"
                                 "${ownDefs};${defs}")
  endif()
  if(private)
    get_target_property(type ${target} TYPE)
    if(type STREQUAL "INTERFACE_LIBRARY")
      message(FATAL_ERROR "cubeao_check_headers(${target}): an INTERFACE library has no private headers")
    endif()
    _cubeao_target_list(privateDefs ${target} COMPILE_DEFINITIONS)
    _cubeao_header_closure("${allLinks}" depDirs libs defs)
    _cubeao_header_check_library(${target}_private_header_check "${private}" "${ownDirs};${depDirs}"
                                 "${libs}" "${privateDefs};${defs}")
  endif()

  # The library's own .cpp files: their quoted includes, checked by cmake/IncludeCheck.cmake against
  # a staged directory of the library's headers and those of every cubeao library it links.
  get_target_property(sources ${target} SOURCES)
  if(sources)
    get_target_property(sourceDir ${target} SOURCE_DIR)
    set(absolute "")
    foreach(src IN LISTS sources)
      if(src MATCHES "\\.(cpp|cc|c)$")
        get_filename_component(src "${src}" ABSOLUTE BASE_DIR "${sourceDir}")
        list(APPEND absolute "${src}")
      endif()
    endforeach()
    _cubeao_header_closure("${allLinks}" depDirs libs defs)
    set(name ${target}_include_check)
    _cubeao_stage_headers(${name} "${ownDirs};${depDirs}" include)
    set(stamp "${CMAKE_BINARY_DIR}/header_check/${name}/sources.stamp")
    string(REPLACE ";" "|" sourceArg "${absolute}")  # one command-line argument
    add_custom_command(OUTPUT "${stamp}"
      COMMAND ${CMAKE_COMMAND} "-DINCLUDE_DIR=${include}" "-DSOURCES=${sourceArg}" "-DSTAMP=${stamp}"
              "-DTARGET=${target}" -P "${_cubeao_header_check_dir}/IncludeCheck.cmake"
      DEPENDS ${absolute} "${_cubeao_header_check_dir}/IncludeCheck.cmake"
      COMMENT "Checking the includes of ${target}'s sources"
      VERBATIM)
    add_custom_target(${name} ALL DEPENDS "${stamp}")
  endif()
endfunction()
