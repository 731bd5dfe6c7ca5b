# Install rules, the CMake package config, pkg-config's sgfx.pc and the Debian packages (CPack).
# Everything public lands under include/sgfx/: nothing at the top of include/ (no KHR/, no glad/:
# sgfx's GL loader is private, see third_party/glad/CMakeLists.txt).
#
# Components: runtime (the shared libraries), dev (headers, static libraries or .so links, CMake
# config, sgfx.pc) and tools (sgfx-view). `cpack -G DEB` in a shared build makes libsgfx0,
# libsgfx-dev and sgfx-tools from them.
set(SGFX_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/sgfx)

install(TARGETS sgfx sgfx_scenegraph sgfx_nodes sgfx_loaders EXPORT sgfxTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT dev
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT runtime NAMELINK_COMPONENT dev
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY scenegraph/include/ loaders/include/ nodes/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
        COMPONENT dev)
# The 0.1 effect-header spellings (<fog/FogNode.h>), forwarding with a warning, in 0.2 only.
install(DIRECTORY nodes/compat/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/sgfx/compat COMPONENT dev)
install(EXPORT sgfxTargets NAMESPACE sgfx:: DESTINATION ${SGFX_CMAKE_DIR} COMPONENT dev)

# A shared sgfx keeps glfw, TinyGLTF and OpenMesh to itself; a static one passes them on.
if(BUILD_SHARED_LIBS)
  set(SGFX_CONFIG_PRIVATE_DEPENDENCIES "")
else()
  set(SGFX_CONFIG_PRIVATE_DEPENDENCIES
      "find_dependency(glfw3 3.3)\nfind_dependency(TinyGLTF CONFIG)\nfind_dependency(OpenMesh CONFIG)")
  if(SGFX_HAVE_MESHOPTIMIZER)
    string(APPEND SGFX_CONFIG_PRIVATE_DEPENDENCIES "\nfind_dependency(meshoptimizer CONFIG)")
  endif()
endif()
include(CMakePackageConfigHelpers)
configure_package_config_file(cmake/sgfxConfig.cmake.in ${PROJECT_BINARY_DIR}/sgfxConfig.cmake
                              INSTALL_DESTINATION ${SGFX_CMAKE_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/sgfxConfigVersion.cmake COMPATIBILITY SameMajorVersion)
install(FILES ${PROJECT_BINARY_DIR}/sgfxConfig.cmake ${PROJECT_BINARY_DIR}/sgfxConfigVersion.cmake
        DESTINATION ${SGFX_CMAKE_DIR} COMPONENT dev)

# pkg-config: `pkg-config --cflags --libs sgfx` (add --static against static libraries). The prefix
# is the configured one (the Debian packages: /usr); a staged install overrides it with
# --define-variable=prefix=... (tests/packaging/check_install.sh).
# A shared sgfx keeps its libraries to itself: pkgconf reads Requires.private even without --static,
# so listing them would make users install glfw's, OSMesa's... -dev packages for nothing.
if(BUILD_SHARED_LIBS)
  set(SGFX_PC_REQUIRES_PRIVATE "")
  set(SGFX_PC_LIBS_PRIVATE "")
else()
  set(SGFX_PC_REQUIRES_PRIVATE "Requires.private: glfw3 osmesa stb tinygltf openmesh\n")
  set(SGFX_PC_LIBS_PRIVATE "Libs.private: -ldl")
  if(SGFX_HAVE_MESHOPTIMIZER) # Debian's meshoptimizer has no .pc file
    string(APPEND SGFX_PC_LIBS_PRIVATE " -lmeshoptimizer")
  endif()
endif()
configure_file(cmake/sgfx.pc.in ${PROJECT_BINARY_DIR}/sgfx.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/sgfx.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig COMPONENT dev)

if(TARGET sgfx-view)
  install(TARGETS sgfx-view RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT tools)
endif()

# ---- Debian packages: cpack -G DEB (from a -DBUILD_SHARED_LIBS=ON build; scripts/package.sh)
if(NOT BUILD_SHARED_LIBS)
  # libsgfx0 would be empty and libsgfx-dev would depend on it: packages come from a shared build.
  return()
endif()
set(CPACK_PACKAGE_NAME sgfx)
set(CPACK_PACKAGE_VENDOR "sgfx developers")
set(CPACK_PACKAGE_CONTACT "sgfx developers <sgfx@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "Scene graph with effect nodes for trainers and simulators")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_GENERATOR DEB)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_COMPONENTS_ALL runtime dev)
if(TARGET sgfx-view)
  list(APPEND CPACK_COMPONENTS_ALL tools)
endif()
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION libs)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# sgfx-view's own libraries are in libsgfx0, not installed while packaging: let dpkg-shlibdeps see them.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS_PRIVATE_DIRS
    ${PROJECT_BINARY_DIR}/scenegraph ${PROJECT_BINARY_DIR}/nodes ${PROJECT_BINARY_DIR}/loaders)
set(CPACK_DEBIAN_RUNTIME_PACKAGE_NAME libsgfx${PROJECT_VERSION_MAJOR})
set(CPACK_DEBIAN_RUNTIME_DESCRIPTION "sgfx scene graph: shared libraries")
set(CPACK_DEBIAN_DEV_PACKAGE_NAME libsgfx-dev)
set(CPACK_DEBIAN_DEV_PACKAGE_SECTION libdevel)
set(CPACK_DEBIAN_DEV_PACKAGE_DEPENDS "libsgfx${PROJECT_VERSION_MAJOR} (= ${PROJECT_VERSION}), libglm-dev")
set(CPACK_DEBIAN_DEV_DESCRIPTION "sgfx scene graph: headers, CMake package config and pkg-config file")
set(CPACK_DEBIAN_TOOLS_PACKAGE_NAME sgfx-tools)
set(CPACK_DEBIAN_TOOLS_PACKAGE_SECTION graphics)
set(CPACK_DEBIAN_TOOLS_PACKAGE_DEPENDS "libsgfx${PROJECT_VERSION_MAJOR} (= ${PROJECT_VERSION})")
set(CPACK_DEBIAN_TOOLS_DESCRIPTION "sgfx scene graph: sgfx-view, a model viewer with the effects")
include(CPack)
