# The commit a build was made from, for `veil --version`, reports and image headers
# (src/io/provenance.h). Run at every build by the veil_git_commit target:
#
#   cmake -DSOURCE_DIR=<repo> -DTEMPLATE=<version_info.h.in> -DOUTPUT=<header>
#         -DVERSION=<project version> -P git_commit.cmake
#
# `git describe --always --dirty --abbrev=12` names the commit (with "-dirty" when tracked
# files differ from it). configure_file rewrites the header only when its text changes, so an
# unchanged commit rebuilds nothing and a new one rebuilds the one unit that includes it. A
# source tree without its own .git (a tarball) says "unknown".
cmake_minimum_required(VERSION 3.25)

foreach(var SOURCE_DIR TEMPLATE OUTPUT VERSION)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "git_commit.cmake: ${var} is not set")
  endif()
endforeach()

set(VEIL_GIT_COMMIT "unknown")
set(VEIL_GIT_DIRTY 0)
set(VEIL_VERSION_TEXT "${VERSION}")
find_program(GIT_EXECUTABLE git)
if(GIT_EXECUTABLE AND EXISTS "${SOURCE_DIR}/.git")
  execute_process(COMMAND "${GIT_EXECUTABLE}" describe --always --dirty --abbrev=12
                  WORKING_DIRECTORY "${SOURCE_DIR}" OUTPUT_VARIABLE described
                  RESULT_VARIABLE rc OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  if(rc EQUAL 0 AND described MATCHES "^[A-Za-z0-9._/+-]+$")
    set(VEIL_GIT_COMMIT "${described}")
    if(described MATCHES "-dirty$")
      set(VEIL_GIT_DIRTY 1)
    endif()
  endif()
endif()
configure_file("${TEMPLATE}" "${OUTPUT}" @ONLY)
