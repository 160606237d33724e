file(REMOVE_RECURSE
  "CMakeFiles/bullet_bridge.dir/src/smoke.cpp.o"
  "CMakeFiles/bullet_bridge.dir/src/smoke.cpp.o.d"
  "libbullet_bridge.a"
  "libbullet_bridge.pdb"
)

# Per-language clean rules from dependency scanning.
foreach(lang CXX)
  include(CMakeFiles/bullet_bridge.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
