// The source of juggle_test_pch (CMakeLists.txt): the target exists for its precompiled header.
