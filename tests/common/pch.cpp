// The source that builds the test programs' precompiled header (tests/CMakeLists.txt,
// dynid_test_pch); it has no code of its own.
