file(REMOVE_RECURSE
  "CMakeFiles/test_sanity.dir/unit/test_sanity.cpp.o"
  "CMakeFiles/test_sanity.dir/unit/test_sanity.cpp.o.d"
  "test_sanity"
  "test_sanity.pdb"
  "test_sanity[1]_tests.cmake"
)

# Per-language clean rules from dependency scanning.
foreach(lang CXX)
  include(CMakeFiles/test_sanity.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
