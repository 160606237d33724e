# Empty dependencies file for test_sanity.
# This may be replaced when dependencies are built.
