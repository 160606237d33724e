# Debian's Bullet of one precision as an imported target:
#   xpbd_bullet::bullet-float64   double: BulletConfig-float64.cmake, -lBullet*-float64
#   xpbd_bullet::bullet-float     float:  BulletConfig.cmake, -lBullet*
# with Bullet's include directory and the libraries the bridge uses
# (BulletSoftBody, BulletDynamics, BulletCollision, LinearMath), but without
# BT_USE_DOUBLE_PRECISION: like Bullet's own CMake config, which leaves
# BULLET_DEFINITIONS to its user, the package does not define it for its
# consumers (xpbd_bullet/precision_check.hpp, docs/embedding.md).
#
# Used by the build tree (bullet_bridge/CMakeLists.txt) and by the installed
# xpbd_bullet-config.cmake alike, so that the exported bullet_bridge target
# names the same Bullet target in both. The same file is installed by the
# float and the double build.
#
# Use:
#   xpbd_bullet_bullet_config(<float64|float> <out-var>)  Bullet's config file name
#   find_package(Bullet CONFIG REQUIRED CONFIGS <that name>)   (or find_dependency)
#   xpbd_bullet_add_bullet_target(<float64|float> <error-var>)
# The last one reads the BULLET_* variables Bullet's config set and leaves an
# error message in <error-var> ("" on success).

function(xpbd_bullet_bullet_config precision out)
  if(precision STREQUAL "float64")
    set(${out} BulletConfig-float64.cmake PARENT_SCOPE)
  else()
    set(${out} BulletConfig.cmake PARENT_SCOPE)
  endif()
endfunction()

function(xpbd_bullet_add_bullet_target precision error)
  set(${error} "" PARENT_SCOPE)
  set(target xpbd_bullet::bullet-${precision})
  if(TARGET ${target})
    return()
  endif()
  set(suffix "")
  if(precision STREQUAL "float64")
    set(suffix -float64)
  endif()
  # Debian's BulletConfig*.cmake gives its directories relative to
  # BULLET_ROOT_DIR ("include/bullet", "lib/x86_64-linux-gnu").
  set(include_dirs "")
  foreach(dir IN LISTS BULLET_INCLUDE_DIRS)
    if(NOT IS_ABSOLUTE "${dir}")
      set(dir "${BULLET_ROOT_DIR}/${dir}")
    endif()
    list(APPEND include_dirs "${dir}")
  endforeach()
  set(library_dirs "")
  foreach(dir IN LISTS BULLET_LIBRARY_DIRS)
    if(NOT IS_ABSOLUTE "${dir}")
      set(dir "${BULLET_ROOT_DIR}/${dir}")
    endif()
    list(APPEND library_dirs "${dir}")
  endforeach()
  set(libraries "")
  foreach(name BulletSoftBody BulletDynamics BulletCollision LinearMath)
    set(var XPBD_BULLET_${precision}_${name}_LIBRARY)
    find_library(${var} NAMES ${name}${suffix} PATHS ${library_dirs} NO_DEFAULT_PATH)
    mark_as_advanced(${var})
    if(NOT ${var})
      set(${error} "xpbd_bullet: ${name}${suffix} not found in '${library_dirs}' (Bullet's config: ${Bullet_CONFIG}); install Debian's libbullet-dev" PARENT_SCOPE)
      return()
    endif()
    list(APPEND libraries ${${var}})
  endforeach()
  add_library(${target} INTERFACE IMPORTED)
  set_target_properties(${target} PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${include_dirs}"
    INTERFACE_LINK_LIBRARIES "${libraries}")
endfunction()
