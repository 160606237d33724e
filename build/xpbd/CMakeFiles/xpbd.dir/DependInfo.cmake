
# Consider dependencies only in project.
set(CMAKE_DEPENDS_IN_PROJECT_ONLY OFF)

# The set of languages for which implicit dependencies are needed:
set(CMAKE_DEPENDS_LANGUAGES
  )

# The set of dependency files which are needed:
set(CMAKE_DEPENDS_DEPENDENCY_FILES
  "/work/main/xpbd/src/builders.cpp" "xpbd/CMakeFiles/xpbd.dir/src/builders.cpp.o" "gcc" "xpbd/CMakeFiles/xpbd.dir/src/builders.cpp.o.d"
  "/work/main/xpbd/src/compile.cpp" "xpbd/CMakeFiles/xpbd.dir/src/compile.cpp.o" "gcc" "xpbd/CMakeFiles/xpbd.dir/src/compile.cpp.o.d"
  "/work/main/xpbd/src/diagnostics.cpp" "xpbd/CMakeFiles/xpbd.dir/src/diagnostics.cpp.o" "gcc" "xpbd/CMakeFiles/xpbd.dir/src/diagnostics.cpp.o.d"
  "/work/main/xpbd/src/step.cpp" "xpbd/CMakeFiles/xpbd.dir/src/step.cpp.o" "gcc" "xpbd/CMakeFiles/xpbd.dir/src/step.cpp.o.d"
  )

# Targets to which this target links.
set(CMAKE_TARGET_LINKED_INFO_FILES
  )

# Fortran module output directory.
set(CMAKE_Fortran_TARGET_MODULE_DIR "")
