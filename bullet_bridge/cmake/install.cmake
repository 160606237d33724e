# cmake --install: the libraries, their headers, the CMake package
# xpbd_bullet and a pkg-config file. A float build (XPBD_DOUBLE=OFF) and a
# double build (XPBD_DOUBLE=ON) install side by side into one prefix; <p> is
# the precision (float64 or float), <s> the library suffix (-float64 for
# double, none for float, as Debian names Bullet's libraries):
#
#   include/xpbd/, include/xpbd_bullet/       headers, the same in both builds
#   include/xpbd_bullet-<p>/xpbd/config.hpp   the generated precision header
#   lib/libxpbd<s>.a, lib/libxpbd_bullet_bridge<s>.a
#   lib/libxpbd_io<s>.a                        if xpbd_io was built (tinyobjloader found)
#   lib/cmake/xpbd_bullet/
#     xpbd_bullet-config.cmake, xpbd_bullet-config-version.cmake,
#     xpbd_bullet-bullet.cmake                 the same in both builds
#     xpbd_bullet-<p>-targets*.cmake           xpbd_bullet::xpbd, xpbd_bullet::bullet_bridge
#     xpbd_bullet-<p>-io-targets*.cmake        xpbd_bullet::io
#   lib/pkgconfig/xpbd_bullet.pc (float), xpbd_bullet-float64.pc (double)
#
# Static libraries by default; BUILD_SHARED_LIBS=ON builds shared ones
# (lib<name><s>.so.<major.minor>).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

if(XPBD_DOUBLE)
  set(XPBD_SUFFIX -float64)
  set(XPBD_REAL double)
  set(XPBD_PC_NAME xpbd_bullet-float64)
  set(XPBD_PC_BULLET bullet-float64)
else()
  set(XPBD_SUFFIX "")
  set(XPBD_REAL float)
  set(XPBD_PC_NAME xpbd_bullet)
  set(XPBD_PC_BULLET bullet)
endif()
set(XPBD_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/xpbd_bullet)
set(XPBD_PRECISION_INCLUDEDIR ${CMAKE_INSTALL_INCLUDEDIR}/xpbd_bullet-${XPBD_PRECISION})

# File names, export names, and the precision as an exported property (the
# package config refuses to load the other precision's targets next to it).
set(xpbd_install_targets xpbd bullet_bridge)
set_target_properties(xpbd PROPERTIES OUTPUT_NAME xpbd${XPBD_SUFFIX} EXPORT_NAME xpbd)
set_target_properties(bullet_bridge PROPERTIES
  OUTPUT_NAME xpbd_bullet_bridge${XPBD_SUFFIX} EXPORT_NAME bullet_bridge)
if(TARGET xpbd_io)
  set_target_properties(xpbd_io PROPERTIES OUTPUT_NAME xpbd_io${XPBD_SUFFIX} EXPORT_NAME io)
  list(APPEND xpbd_install_targets xpbd_io)
endif()
# Position-independent code, static libraries included, so that an
# application can link them into its own shared library or plugin
# (tests/consumer builds one).
foreach(t IN LISTS xpbd_install_targets)
  set_target_properties(${t} PROPERTIES
    POSITION_INDEPENDENT_CODE ON
    VERSION ${PROJECT_VERSION}
    SOVERSION ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR}
    XPBD_BULLET_PRECISION ${XPBD_PRECISION}
    EXPORT_PROPERTIES XPBD_BULLET_PRECISION)
  target_include_directories(${t} PUBLIC $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
endforeach()
target_include_directories(xpbd PUBLIC $<INSTALL_INTERFACE:${XPBD_PRECISION_INCLUDEDIR}>)

# Libraries and their exported targets.
install(TARGETS xpbd bullet_bridge EXPORT xpbd_bullet-${XPBD_PRECISION}-targets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(EXPORT xpbd_bullet-${XPBD_PRECISION}-targets
  NAMESPACE xpbd_bullet:: DESTINATION ${XPBD_CMAKE_DIR})
if(TARGET xpbd_io)
  install(TARGETS xpbd_io EXPORT xpbd_bullet-${XPBD_PRECISION}-io-targets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  install(EXPORT xpbd_bullet-${XPBD_PRECISION}-io-targets
    NAMESPACE xpbd_bullet:: DESTINATION ${XPBD_CMAKE_DIR})
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/xpbd/io/include/
    DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} FILES_MATCHING PATTERN "*.hpp")
endif()

# Headers: the shared ones, and the precision header in its own directory.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/xpbd/include/ ${PROJECT_SOURCE_DIR}/bullet_bridge/include/
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} FILES_MATCHING PATTERN "*.hpp")
install(FILES ${XPBD_GENERATED_INCLUDE_DIR}/xpbd/config.hpp
  DESTINATION ${XPBD_PRECISION_INCLUDEDIR}/xpbd)

# The package config, its version file and the Bullet helper: the same
# files from both builds.
configure_package_config_file(${PROJECT_SOURCE_DIR}/bullet_bridge/cmake/xpbd_bullet-config.cmake.in
  ${PROJECT_BINARY_DIR}/xpbd_bullet-config.cmake
  INSTALL_DESTINATION ${XPBD_CMAKE_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/xpbd_bullet-config-version.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES
  ${PROJECT_BINARY_DIR}/xpbd_bullet-config.cmake
  ${PROJECT_BINARY_DIR}/xpbd_bullet-config-version.cmake
  ${PROJECT_SOURCE_DIR}/bullet_bridge/cmake/xpbd_bullet-bullet.cmake
  DESTINATION ${XPBD_CMAKE_DIR})

# pkg-config, relocatable: the prefix is found from the .pc file's own
# directory (pcfiledir), so that cmake --install --prefix <dir> works.
set(xpbd_pc_dir ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
if(IS_ABSOLUTE "${CMAKE_INSTALL_LIBDIR}" OR IS_ABSOLUTE "${CMAKE_INSTALL_INCLUDEDIR}")
  set(XPBD_PC_PREFIX "${CMAKE_INSTALL_PREFIX}")
  set(XPBD_PC_LIBDIR "${CMAKE_INSTALL_FULL_LIBDIR}")
  set(XPBD_PC_INCLUDEDIR "${CMAKE_INSTALL_FULL_INCLUDEDIR}")
else()
  file(RELATIVE_PATH xpbd_pc_up /p/${xpbd_pc_dir} /p)
  string(REGEX REPLACE "/$" "" xpbd_pc_up "${xpbd_pc_up}")
  set(XPBD_PC_PREFIX "\${pcfiledir}/${xpbd_pc_up}")
  set(XPBD_PC_LIBDIR "\${prefix}/${CMAKE_INSTALL_LIBDIR}")
  set(XPBD_PC_INCLUDEDIR "\${prefix}/${CMAKE_INSTALL_INCLUDEDIR}")
endif()
configure_file(${PROJECT_SOURCE_DIR}/bullet_bridge/cmake/xpbd_bullet.pc.in
  ${PROJECT_BINARY_DIR}/${XPBD_PC_NAME}.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/${XPBD_PC_NAME}.pc DESTINATION ${xpbd_pc_dir})
