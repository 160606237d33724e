file(REMOVE_RECURSE
  "CMakeFiles/xpbd.dir/src/builders.cpp.o"
  "CMakeFiles/xpbd.dir/src/builders.cpp.o.d"
  "CMakeFiles/xpbd.dir/src/compile.cpp.o"
  "CMakeFiles/xpbd.dir/src/compile.cpp.o.d"
  "CMakeFiles/xpbd.dir/src/diagnostics.cpp.o"
  "CMakeFiles/xpbd.dir/src/diagnostics.cpp.o.d"
  "CMakeFiles/xpbd.dir/src/step.cpp.o"
  "CMakeFiles/xpbd.dir/src/step.cpp.o.d"
  "libxpbd.a"
  "libxpbd.pdb"
)

# Per-language clean rules from dependency scanning.
foreach(lang CXX)
  include(CMakeFiles/xpbd.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
