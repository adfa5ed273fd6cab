# dynid_add_library(NAME SOURCES... DEPS... [INTERNAL header.hpp...]): one library per module,
# exported as dynid::NAME. Headers live beside the sources (core/rnea.hpp) and are included as
# "core/rnea.hpp"; every public one is installed as include/dynid/<module>/<name>.hpp (or
# include/dynid/<HEADER_DIR>/ for a nested module), so a consumer of find_package(dynid) writes
# #include <dynid/core/rnea.hpp>. The INTERNAL headers (implementation rooms no public header
# includes) are not installed.
function(dynid_add_library name)
  cmake_parse_arguments(ARG "" "HEADER_DIR" "SOURCES;DEPS;INTERNAL" ${ARGN})
  if(NOT ARG_HEADER_DIR)
    set(ARG_HEADER_DIR ${name})
  endif()
  add_library(dynid_${name} ${ARG_SOURCES})
  add_library(dynid::${name} ALIAS dynid_${name})
  set_target_properties(dynid_${name} PROPERTIES EXPORT_NAME ${name} OUTPUT_NAME dynid_${name}
                                                 POSITION_INDEPENDENT_CODE ON)
  target_include_directories(dynid_${name} PUBLIC
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}/dynid>)
  target_link_libraries(dynid_${name} PUBLIC ${ARG_DEPS} PRIVATE $<BUILD_INTERFACE:dynid_warnings>)
  install(TARGETS dynid_${name} EXPORT dynidTargets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
  file(GLOB headers RELATIVE ${CMAKE_CURRENT_SOURCE_DIR} CONFIGURE_DEPENDS
       ${CMAKE_CURRENT_SOURCE_DIR}/*.hpp)
  foreach(header ${ARG_INTERNAL})
    if(NOT header IN_LIST headers)
      message(FATAL_ERROR "dynid_add_library(${name}): no internal header ${header}")
    endif()
  endforeach()
  list(REMOVE_ITEM headers ${ARG_INTERNAL})
  install(FILES ${headers} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/dynid/${ARG_HEADER_DIR})
endfunction()

include(GoogleTest)

# dynid_test_code_options(target): the optimisation level of the tests' own code, for every test
# program and for the precompiled header they share (tests/CMakeLists.txt), which must be built
# with the same flags as the sources that use it.
function(dynid_test_code_options target)
  # The test's own code at -O1 in a release build (the library it tests keeps -O3): half the
  # build's compile time is the ~140 test sources, mostly spent optimising GoogleTest and Eigen
  # instantiations that run once; -O1 (after -O3, so it wins) saves about a fifth of it.
  target_compile_options(${target} PRIVATE $<$<CONFIG:Release>:-O1>)
  # Under the sanitizers (scripts/sanitize.sh: -O1 for everything) the test's own code at -O0:
  # it halves those sources' compile time; what they test is the library, still at -O1.
  if(DYNID_SANITIZE)
    target_compile_options(${target} PRIVATE -O0)
  endif()
endfunction()

# dynid_add_test(path/to/name_test.cpp [SERIAL] DEPS...): one GoogleTest executable per source
# file; the test name mirrors the source path (tests/core/rnea_test.cpp -> core.rnea_test). In
# sanitizer builds the programs listed in DYNID_SANITIZER_SKIPPED_TESTS are not made.
function(dynid_add_test source)
  cmake_parse_arguments(ARG "SERIAL" "" "DEPS" ${ARGN})
  get_filename_component(stem ${source} NAME_WE)
  get_filename_component(dir ${source} DIRECTORY)
  get_filename_component(module ${dir} NAME)
  set(target ${module}_${stem})
  if(DYNID_SANITIZE AND target IN_LIST DYNID_SANITIZER_SKIPPED_TESTS)
    return()  # see tests/CMakeLists.txt
  endif()
  add_executable(${target} ${source})
  target_link_libraries(${target} PRIVATE ${ARG_DEPS} dynid_test_common GTest::gtest_main
                                          dynid_warnings)
  dynid_test_code_options(${target})
  # GoogleTest and Eigen parsed once for every test program (tests/CMakeLists.txt,
  # dynid_test_pch).
  target_precompile_headers(${target} REUSE_FROM dynid_test_pch)
  set_target_properties(${target} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/tests)
  set(environment "")
  if(DYNID_SANITIZE)
    set(environment "LSAN_OPTIONS=suppressions=${PROJECT_SOURCE_DIR}/tests/lsan.supp")
  endif()
  # SERIAL: tests that time a command against its own wall-clock budget run alone (ctest -j2 would
  # otherwise share the two cores with another test after the command has timed its reserve).
  set(serial FALSE)
  if(ARG_SERIAL)
    set(serial TRUE)
  endif()
  gtest_discover_tests(${target} TEST_PREFIX "${module}." DISCOVERY_TIMEOUT 60
                       PROPERTIES RUN_SERIAL ${serial} ENVIRONMENT "${environment}")
endfunction()
