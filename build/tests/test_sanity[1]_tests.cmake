add_test([=[Sanity.Builds]=]  /work/main/build/tests/test_sanity [==[--gtest_filter=Sanity.Builds]==] --gtest_also_run_disabled_tests)
set_tests_properties([=[Sanity.Builds]=]  PROPERTIES WORKING_DIRECTORY /work/main/build/tests SKIP_REGULAR_EXPRESSION [==[\[  SKIPPED \]]==] LABELS unit)
set(  test_sanity_TESTS Sanity.Builds)
