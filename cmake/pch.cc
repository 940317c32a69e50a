// The source of the precompiled-header targets (juggle_add_pch in CMakeLists.txt): each exists
// for its header.
