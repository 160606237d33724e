file(REMOVE_RECURSE
  "CMakeFiles/xpbd-demo.dir/main.cpp.o"
  "CMakeFiles/xpbd-demo.dir/main.cpp.o.d"
  "xpbd-demo"
  "xpbd-demo.pdb"
)

# Per-language clean rules from dependency scanning.
foreach(lang CXX)
  include(CMakeFiles/xpbd-demo.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
