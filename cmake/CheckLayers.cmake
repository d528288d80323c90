# Checks that every include between stages goes the way docs/architecture.md's layer list
# allows: run as `cmake -DROOT=<source dir> -P CheckLayers.cmake` (the build runs it whenever a
# source changes, and ctest runs it). The list, a fenced block tagged `layers`, names each
# stage with the stages it may include, lowest first; a stage may name only stages above it in
# the list, so the layers cannot form a cycle. A stage is a folder: include/rangefuse/<stage>/
# and src/<stage>/ (io/ is stage io; rangefuse/rangefuse.h is stage api). A stage's private
# headers (src/<stage>/*.h) may be included by its own files only.
cmake_minimum_required(VERSION 3.18)
if(NOT ROOT)
  message(FATAL_ERROR "CheckLayers.cmake: give -DROOT=<source dir>")
endif()

file(READ ${ROOT}/docs/architecture.md doc)
string(REGEX MATCH "```layers\n([^`]*)```" block "${doc}")
if(NOT block)
  message(FATAL_ERROR "${ROOT}/docs/architecture.md: no ```layers block")
endif()
string(REGEX REPLACE "```layers\n|```" "" block "${block}")
string(REPLACE "\n" ";" lines "${block}")

set(stages "")
foreach(line ${lines})
  if(line MATCHES "^([a-z]+):(.*)$")
    set(stage ${CMAKE_MATCH_1})
    string(REGEX MATCHALL "[a-z]+" allowed "${CMAKE_MATCH_2}")
    foreach(other ${allowed})
      if(NOT other IN_LIST stages)
        message(FATAL_ERROR "docs/architecture.md: layer ${stage} names ${other}, which is not "
                            "listed before it (the layers would not be a hierarchy)")
      endif()
    endforeach()
    set(may_${stage} ${allowed})
    list(APPEND stages ${stage})
  endif()
endforeach()

# The stage of a file, by its path under ROOT; empty for files outside every stage (tests).
function(stage_of path out)
  set(s "")
  if(path MATCHES "^include/rangefuse/rangefuse\\.h$")
    set(s api)
  elseif(path MATCHES "^include/rangefuse/([a-z]+)/")
    set(s ${CMAKE_MATCH_1})
  elseif(path MATCHES "^src/([a-z]+)/")
    set(s ${CMAKE_MATCH_1})
  elseif(path MATCHES "^io/")
    set(s io)
  endif()
  set(${out} ${s} PARENT_SCOPE)
endfunction()

file(GLOB_RECURSE files RELATIVE ${ROOT} ${ROOT}/include/*.h ${ROOT}/src/*.h ${ROOT}/src/*.cpp
     ${ROOT}/io/*.h ${ROOT}/io/*.cpp)
set(wrong "")
foreach(file ${files})
  stage_of(${file} stage)
  if(NOT stage IN_LIST stages)
    list(APPEND wrong "${file}: its folder '${stage}' is not in the layers")
    continue()
  endif()
  file(STRINGS ${ROOT}/${file} includes REGEX "^#include \"")
  foreach(line ${includes})
    string(REGEX REPLACE "^#include \"([^\"]+)\".*" "\\1" target "${line}")
    if(target MATCHES "^rangefuse/")
      stage_of("include/${target}" to)
    elseif(target MATCHES "/")
      # A path into another folder: another stage's private header.
      list(APPEND wrong "${file}: includes ${target}, a private header of another folder")
      continue()
    else()
      continue()  # its own folder's private header
    endif()
    if(to STREQUAL stage)
      continue()
    endif()
    if(NOT to IN_LIST may_${stage})
      list(APPEND wrong "${file}: includes ${target}, but ${stage} may not depend on ${to}")
    endif()
  endforeach()
endforeach()

if(wrong)
  list(LENGTH wrong count)
  list(JOIN wrong "\n  " text)
  message(FATAL_ERROR "${count} includes break the layers of docs/architecture.md:\n  ${text}")
endif()
list(LENGTH files count)
message(STATUS "layers: ${count} files include only what their layer allows")
