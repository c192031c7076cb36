# cmake/packaging.cmake — `cmake --install` (libraries, public headers, the CMake package with its exported
# targets, the pkg-config file, the `unison` tool) and `cpack -G DEB`.
#
# Installed CMake targets: unison::unison (the shared library; the static one when shared libraries are off) and
# unison::unison_static. Both carry -ffp-contract=off as a compile option of their users (docs/determinism.md).
include(CMakePackageConfigHelpers)

set(UNISON_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/unison)
set(_targets unison_static)
if(TARGET unison_shared)
  list(APPEND _targets unison_shared)
endif()
install(TARGETS ${_targets} EXPORT unisonTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/unison DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
  FILES_MATCHING PATTERN "*.h")
install(FILES ${PROJECT_BINARY_DIR}/include/unison/version.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/unison)
install(EXPORT unisonTargets NAMESPACE unison:: DESTINATION ${UNISON_CMAKE_DIR})

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/unisonConfig.cmake.in
  ${PROJECT_BINARY_DIR}/unisonConfig.cmake INSTALL_DESTINATION ${UNISON_CMAKE_DIR})
# 0.x: a minor version may change the API, so only the same minor version is compatible.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/unisonConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/unisonConfig.cmake ${PROJECT_BINARY_DIR}/unisonConfigVersion.cmake
  DESTINATION ${UNISON_CMAKE_DIR})

set(UNISON_PC_LIBS_PRIVATE "-pthread -lstdc++ -lm")
if(UNISON_XXHASH_LINK)
  set(UNISON_PC_LIBS_PRIVATE "-l${UNISON_XXHASH_LINK} ${UNISON_PC_LIBS_PRIVATE}")
endif()
# The prefix relative to the .pc file, so that an installed tree can be moved (e.g. cmake --install --prefix).
file(RELATIVE_PATH UNISON_PC_PREFIX "/${CMAKE_INSTALL_LIBDIR}/pkgconfig" "/")
string(REGEX REPLACE "/$" "" UNISON_PC_PREFIX "${UNISON_PC_PREFIX}")
configure_file(${PROJECT_SOURCE_DIR}/cmake/unison.pc.in ${PROJECT_BINARY_DIR}/unison.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/unison.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

if(TARGET unison_cli)
  install(TARGETS unison_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()
install(FILES ${PROJECT_SOURCE_DIR}/LICENSE ${PROJECT_SOURCE_DIR}/README.md ${PROJECT_SOURCE_DIR}/CHANGELOG.md
  DESTINATION ${CMAKE_INSTALL_DOCDIR})

# Debian package: cpack -G DEB in the build folder.
set(CPACK_PACKAGE_NAME unison)
set(CPACK_PACKAGE_VENDOR "The Unison authors")
set(CPACK_PACKAGE_CONTACT "The Unison authors")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "Deterministic 2D and 3D rigid-body physics with LCP contact resolution")
set(CPACK_RESOURCE_FILE_LICENSE ${PROJECT_SOURCE_DIR}/LICENSE)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION libdevel)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)  # dependencies of the library and the tool from dpkg-shlibdeps
set(CPACK_DEBIAN_PACKAGE_DEPENDS "libxxhash-dev")  # the static library links xxhash
set(CPACK_GENERATOR DEB)
include(CPack)
