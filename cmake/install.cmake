# `cmake --install build/release --prefix P` (or `make install PREFIX=P`): an installed tree
# that works without the source or build tree (README.md "Install"; docs/cluster.md):
#   P/bin/veil                      the command
#   P/share/veil/shaders/           its shaders: veil reads <its folder>/../share/veil/shaders
#                                   when VEIL_SHADER_DIR is not set (src/gpu/shader.cpp)
#   P/share/veil/datasets/          the example scenes with the meshes and volumes they use
#                                   (scenes/, third_party/ with their licenses)
#   P/lib/python3.X/site-packages/veil   the Python package with its own copy of the shaders
#                                   (python/CMakeLists.txt; component python)
# The command links Veil's libraries statically and the system's shared libraries from their
# standard folders, so it needs no RPATH into the build tree.
include(GNUInstallDirs)
if(TARGET veil)
  install(TARGETS veil RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT veil)
  install(DIRECTORY ${CMAKE_SOURCE_DIR}/shaders/ DESTINATION ${CMAKE_INSTALL_DATADIR}/veil/shaders
          COMPONENT veil)
  install(DIRECTORY ${CMAKE_SOURCE_DIR}/datasets/scenes ${CMAKE_SOURCE_DIR}/datasets/third_party
          DESTINATION ${CMAKE_INSTALL_DATADIR}/veil/datasets COMPONENT veil)
endif()
