# The package a platform builds against: `cmake --install build --prefix DIR` puts the model's
# libraries, their headers (under include/rtsim, in their folders) and rtsimConfig.cmake with the
# exported targets rtsim::model, rtsim::kernels, rtsim::scene (the scene loaders),
# rtsim::config (the readers of hardware and scene files), rtsim::scene_types and rtsim::common;
# `find_package(rtsim)` then finds them and sets rtsim_CONFIG_DIR to the installed configs/
# (share/rtsim/configs: hardware, scene and sweep files) (docs/systemc-integration.md,
# "The package"). `cpack -G DEB` makes a .deb of the same files. The rtsim command is not
# installed: it runs from the build tree, where its report scripts are.
include(CMakePackageConfigHelpers)

set(RTSIM_PACKAGE_TARGETS rtsim_common rtsim_scene_types rtsim_scene rtsim_kernels rtsim_model
  rtsim_config)
foreach(t ${RTSIM_PACKAGE_TARGETS})
  string(REPLACE "rtsim_" "" short ${t})
  set_target_properties(${t} PROPERTIES EXPORT_NAME ${short})
  add_library(rtsim::${short} ALIAS ${t})  # the same names inside the tree
endforeach()

install(TARGETS ${RTSIM_PACKAGE_TARGETS} EXPORT rtsimTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/rtsim)
install(DIRECTORY common scene scene_loader kernels model config_loader
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/rtsim FILES_MATCHING PATTERN "*.h")
# The example TLM-2.0 memory, a fixed-latency target a platform may bind at once: included as in
# the tree, "examples/tlm_memory/fixed_latency_memory.h"
install(FILES examples/tlm_memory/fixed_latency_memory.h
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/rtsim/examples/tlm_memory)

# The hardware, scene and sweep files, found through rtsim_CONFIG_DIR (inside the tree, the
# source's, for the examples built with it)
set(rtsim_CONFIG_DIR ${PROJECT_SOURCE_DIR}/configs)
set(RTSIM_CONFIG_INSTALL_DIR ${CMAKE_INSTALL_DATADIR}/rtsim/configs)
install(DIRECTORY configs/ DESTINATION ${RTSIM_CONFIG_INSTALL_DIR})

set(RTSIM_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/rtsim)
install(EXPORT rtsimTargets NAMESPACE rtsim:: DESTINATION ${RTSIM_CMAKE_DIR})
configure_package_config_file(cmake/rtsimConfig.cmake.in
  ${PROJECT_BINARY_DIR}/rtsimConfig.cmake INSTALL_DESTINATION ${RTSIM_CMAKE_DIR}
  PATH_VARS RTSIM_CONFIG_INSTALL_DIR)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/rtsimConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/rtsimConfig.cmake ${PROJECT_BINARY_DIR}/rtsimConfigVersion.cmake
  DESTINATION ${RTSIM_CMAKE_DIR})
# The examples' sources, to build against the installed package
install(DIRECTORY examples/ DESTINATION ${CMAKE_INSTALL_DATADIR}/rtsim/examples)

set(CPACK_PACKAGE_NAME rtsim-dev)
set(CPACK_PACKAGE_VENDOR "rtsim")
set(CPACK_PACKAGE_CONTACT "rtsim maintainers <rtsim@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
  "SystemC TLM model of a ray-tracing accelerator with LVB shadow-ray culling (library)")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
# What a project that links the static libraries needs (Debian 12 package names)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "libsystemc-dev, libfmt-dev, libglm-dev, libyaml-cpp-dev, \
nlohmann-json3-dev, libtinyobjloader-dev, libtinygltf-dev, libmeshoptimizer-dev, libembree-dev, pkg-config, cmake")
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
include(CPack)
