# Per-target include folders: a module's headers are visible only to code that links the module.
#
# Headers stay next to their sources (src/<module>/x.h, included as "module/x.h"), but no target
# publishes src/ itself. Instead each library publishes a folder of its own in the build tree,
# BUILD/module_include/<target>/, holding links to its headers at their src/-relative paths. A
# target sees its own folder and the folders of the libraries it links PUBLIC-ly (directly or through
# a chain of PUBLIC links), so `#include "bundle/manifest.h"` in a module that does not link
# motionfork_bundle is a compile error, not a convention. tests/architecture_check.py checks the
# same rule on the source text, and ARCHITECTURE.md lists which target may link which.
#
#   motionfork_publish_headers(<target>)                 every *.h / *.inc beside the CMakeLists.txt
#   motionfork_publish_headers(<target> HEADERS a.h ...) these headers (a folder shared by targets)
#   motionfork_publish_headers(<target> EXCLUDE a.h ...) the folder's headers but these
function(motionfork_publish_headers target)
  cmake_parse_arguments(arg "" "" "HEADERS;EXCLUDE" ${ARGN})
  if(arg_HEADERS)
    set(headers ${arg_HEADERS})
  else()
    file(GLOB headers CONFIGURE_DEPENDS RELATIVE ${CMAKE_CURRENT_SOURCE_DIR}
         ${CMAKE_CURRENT_SOURCE_DIR}/*.h ${CMAKE_CURRENT_SOURCE_DIR}/*.inc)
    if(arg_EXCLUDE)
      list(REMOVE_ITEM headers ${arg_EXCLUDE})
    endif()
  endif()
  set(root ${PROJECT_BINARY_DIR}/module_include/${target})
  file(REMOVE_RECURSE ${root})  # no stale link to a header that was removed or moved
  foreach(h IN LISTS headers)
    set(source ${CMAKE_CURRENT_SOURCE_DIR}/${h})
    if(NOT EXISTS ${source})
      message(FATAL_ERROR "motionfork_publish_headers(${target}): no header ${source}")
    endif()
    file(RELATIVE_PATH rel ${PROJECT_SOURCE_DIR}/src ${source})
    get_filename_component(dir ${root}/${rel} DIRECTORY)
    file(MAKE_DIRECTORY ${dir})
    file(CREATE_LINK ${source} ${root}/${rel} SYMBOLIC)
  endforeach()
  target_include_directories(${target} PUBLIC $<BUILD_INTERFACE:${root}>)
endfunction()

# One library module: every *.cc beside the CMakeLists.txt, its headers published as above, and its
# links. TORCH: a LibTorch module (links motionfork_torch_util, reuses its precompiled header).
#
#   motionfork_add_module(<target> [TORCH] [PUBLIC lib ...] [PRIVATE lib ...])
function(motionfork_add_module target)
  cmake_parse_arguments(arg "TORCH" "" "PUBLIC;PRIVATE" ${ARGN})
  file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*.cc)
  add_library(${target} ${sources})
  motionfork_publish_headers(${target})
  if(arg_TORCH)
    list(APPEND arg_PUBLIC motionfork_torch_util)
  endif()
  target_link_libraries(${target} PUBLIC ${arg_PUBLIC} PRIVATE ${arg_PRIVATE})
  if(arg_TORCH)
    target_precompile_headers(${target} REUSE_FROM motionfork_torch_util)
  endif()
endfunction()
