// The source of the xpbd_test_pch_<label> targets (tests/CMakeLists.txt):
// they exist to build each label's precompiled headers once, which every
// test of the label then reuses. Nothing to compile here.
