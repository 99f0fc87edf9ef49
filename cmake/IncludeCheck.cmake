# Run by cmake/HeaderCheck.cmake at build time (cmake -P): every quoted #include in a library's own
# source files must resolve beside the file or under the library's staged include directory (its own
# headers and those of the cubeao libraries it links, PRIVATE ones included). Headers are compiled
# alone by the header check; this covers the .cpp files, which compile against the shared `src`
# include path and so would not notice an include of a higher layer.
#   -DINCLUDE_DIR=<staged dir> -DSOURCES=<a|b|...> -DSTAMP=<file written on success> -DTARGET=<name>
string(REPLACE "|" ";" SOURCES "${SOURCES}")
set(bad "")
foreach(src IN LISTS SOURCES)
  get_filename_component(here "${src}" DIRECTORY)
  file(STRINGS "${src}" lines REGEX "^[ \t]*#[ \t]*include[ \t]*\"")
  foreach(line IN LISTS lines)
    string(REGEX MATCH "\"([^\"]+)\"" _ "${line}")
    set(inc "${CMAKE_MATCH_1}")
    if(NOT EXISTS "${here}/${inc}" AND NOT EXISTS "${INCLUDE_DIR}/${inc}")
      string(APPEND bad "\n  ${src}: #include \"${inc}\"")
    endif()
  endforeach()
endforeach()
if(bad)
  message(FATAL_ERROR "${TARGET}: includes outside the library and its declared dependencies "
                      "(a higher layer, or a missing target_link_libraries):${bad}")
endif()
file(TOUCH "${STAMP}")
