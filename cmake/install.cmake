# `cmake --install BUILD [--prefix PREFIX]`: motionfork as a CMake package another project finds
# with find_package(motionfork) and links as motionfork::api.
#   include/motionfork/motionfork.h     the public API (std types only), version.h its version
#   lib/libmotionfork_*.a               motionfork_api and the static libraries it is built on
#   share/motionfork/configs/           the shipped configs (the API looks here; src/api)
#   lib/cmake/motionfork/               motionforkConfig.cmake, its version file, the targets
# Every rule is in component "sdk" (`--component sdk` installs just this).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

include(${CMAKE_CURRENT_LIST_DIR}/link_closure.cmake)

motionfork_link_closure(motionfork_api MOTIONFORK_EXPORTED_TARGETS MOTIONFORK_EXTERNAL_TARGETS)

# The packages defining those external targets: find_dependency()'d by motionforkConfig.cmake.
set(MOTIONFORK_PACKAGE_DEPENDENCIES "")
foreach(lib IN LISTS MOTIONFORK_EXTERNAL_TARGETS)
  if(lib MATCHES "^([A-Za-z0-9_]+)::")  # Eigen3::Eigen, LibArchive::LibArchive, ...
    list(APPEND MOTIONFORK_PACKAGE_DEPENDENCIES ${CMAKE_MATCH_1})
  elseif(lib MATCHES "^torch")
    list(APPEND MOTIONFORK_PACKAGE_DEPENDENCIES Torch)
  elseif(lib STREQUAL "yaml-cpp")
    list(APPEND MOTIONFORK_PACKAGE_DEPENDENCIES yaml-cpp)
  elseif(lib STREQUAL "gloo")
    list(APPEND MOTIONFORK_PACKAGE_DEPENDENCIES Gloo)
  else()
    message(WARNING "cmake/install.cmake: motionfork_api links '${lib}'; add the package that "
                    "defines it here, or find_package(motionfork) users cannot link")
  endif()
endforeach()
list(REMOVE_DUPLICATES MOTIONFORK_PACKAGE_DEPENDENCIES)

foreach(t IN LISTS MOTIONFORK_EXPORTED_TARGETS)
  string(REGEX REPLACE "^motionfork_" "" export_name ${t})
  set_target_properties(${t} PROPERTIES EXPORT_NAME ${export_name})
  # Internal headers are not installed: their folders (src/) hold for the build tree only.
  get_target_property(dirs ${t} INTERFACE_INCLUDE_DIRECTORIES)
  if(dirs)
    list(TRANSFORM dirs REPLACE "^([^$].*)$" "$<BUILD_INTERFACE:\\1>")
    set_target_properties(${t} PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${dirs}")
  endif()
endforeach()

set(MOTIONFORK_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/motionfork)
install(TARGETS ${MOTIONFORK_EXPORTED_TARGETS} EXPORT motionforkTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT sdk
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT sdk)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/motionfork
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} COMPONENT sdk
        PATTERN evaluate.h EXCLUDE)  # motionfork_api_eval is not installed (build tree only)
install(FILES ${PROJECT_BINARY_DIR}/include/motionfork/version.h
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/motionfork COMPONENT sdk)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/configs/
        DESTINATION ${MOTIONFORK_INSTALL_CONFIG_DIR} COMPONENT sdk)
install(EXPORT motionforkTargets NAMESPACE motionfork:: FILE motionforkTargets.cmake
        DESTINATION ${MOTIONFORK_CMAKE_DIR} COMPONENT sdk)
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/motionforkConfig.cmake.in
  ${PROJECT_BINARY_DIR}/motionforkConfig.cmake
  INSTALL_DESTINATION ${MOTIONFORK_CMAKE_DIR}
  PATH_VARS MOTIONFORK_INSTALL_CONFIG_DIR)
# 0.x: minor versions may break the API.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/motionforkConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/motionforkConfig.cmake
              ${PROJECT_BINARY_DIR}/motionforkConfigVersion.cmake
        DESTINATION ${MOTIONFORK_CMAKE_DIR} COMPONENT sdk)
