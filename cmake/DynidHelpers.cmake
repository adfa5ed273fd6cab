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
  # The test's own code at -O0 in a release build too (after -O3, so it wins; the library it
  # tests, linked first (below), and the shared test helpers (dynid_test_common) keep -O3): the
  # test sources' compile time is mostly spent optimising GoogleTest and Eigen instantiations that
  # run once. Measured on this 2-core machine (2026-12-04, CPU-s from .ninja_log): the test
  # programs' objects 909 CPU-s at -O1, 504 at -O0; the release suite 556 s against 510 s, most of
  # it one test's dense reference SVD in its own code, since done on the QR factor.
  target_compile_options(${target} PRIVATE $<$<CONFIG:Release>:-O0>)
  # Under the sanitizers (scripts/sanitize.sh: -O1 for everything) the test's own code at -O0
  # as well: what they test is the library, still at -O1.
  if(DYNID_SANITIZE)
    target_compile_options(${target} PRIVATE -O0)
  endif()
endfunction()

# dynid_static_closure(out targets...): the dynid static libraries (not the tests' own) that
# `targets` link, directly or through each other.
function(dynid_static_closure out)
  set(seen "")
  set(found "")
  set(queue ${ARGN})
  while(queue)
    list(POP_FRONT queue item)
    string(REGEX REPLACE "^\\$<(LINK_ONLY|BUILD_INTERFACE):(.*)>$" "\\2" item "${item}")
    if(NOT TARGET ${item})
      continue()
    endif()
    get_target_property(aliased ${item} ALIASED_TARGET)
    if(aliased)
      set(item ${aliased})
    endif()
    if(item IN_LIST seen OR NOT item MATCHES "^dynid_")
      continue()
    endif()
    list(APPEND seen ${item})
    get_target_property(type ${item} TYPE)
    if(type STREQUAL "INTERFACE_LIBRARY")
      get_target_property(deps ${item} INTERFACE_LINK_LIBRARIES)
    else()
      get_target_property(deps ${item} LINK_LIBRARIES)
    endif()
    if(deps)
      list(APPEND queue ${deps})
    endif()
    if(type STREQUAL "STATIC_LIBRARY" AND NOT item MATCHES "^dynid_test_")
      list(APPEND found ${item})
    endif()
  endwhile()
  set(${out} ${found} PARENT_SCOPE)
endfunction()

# dynid_add_tests(name [SERIAL] [PREFIX prefix] SOURCES tests... DEPS libraries...): one
# GoogleTest program, tests/<name>_tests, of a module's test sources (each mirrors the source it
# tests: tests/core/rnea_test.cpp tests core/rnea.cpp); its tests are named PREFIX.Suite.Test,
# PREFIX being name unless given. In a unity build (the scripts') a program's sources are one
# translation unit, so GoogleTest's, Eigen's and dynid's templates are instantiated once per module,
# not once per source (docs/TOUR.md, "The test suite and its time", has what it saves). So a test
# source must not define a helper another source of its module defines: those live in
# tests/common. In sanitizer builds the sources in DYNID_SANITIZER_SKIPPED_TESTS are left out.
function(dynid_add_tests name)
  cmake_parse_arguments(ARG "SERIAL" "PREFIX" "SOURCES;DEPS" ${ARGN})
  set(prefix ${name})
  if(ARG_PREFIX)
    set(prefix ${ARG_PREFIX})
  endif()
  set(sources "")
  # Every source any program names, so that tests/CMakeLists.txt can check its skipped list.
  set_property(GLOBAL APPEND PROPERTY DYNID_TEST_SOURCES ${ARG_SOURCES})
  foreach(source IN LISTS ARG_SOURCES)
    if(NOT (DYNID_SANITIZE AND source IN_LIST DYNID_SANITIZER_SKIPPED_TESTS))
      list(APPEND sources ${source})  # see tests/CMakeLists.txt
    endif()
  endforeach()
  if(NOT sources)
    return()
  endif()
  set(target ${name}_tests)
  add_executable(${target} ${sources})
  target_link_libraries(${target} PRIVATE ${ARG_DEPS} dynid_test_common GTest::gtest_main
                                          dynid_warnings)
  dynid_test_code_options(${target})
  # The libraries' own objects come first in the link, whole: a template instantiated both in a
  # library and in the test code (Eigen's kernels, dynid's helpers) is then the library's, as it
  # ships (-O3, or -O1 under the sanitizers), not the test code's (-O1, or -O0 there), which the
  # linker would otherwise keep as the first it saw. Measured under the sanitizers (2-core Zen 3):
  # LeastSquares.ValidationOnHeldOutData took 23.5 s with the test code's Eigen, 5.8 s with the
  # library's.
  dynid_static_closure(libraries ${ARG_DEPS} dynid_test_common)
  if(libraries)  # none in a shared build (static libraries only)
    set(archives "")
    foreach(library IN LISTS libraries)
      list(APPEND archives $<TARGET_FILE:${library}>)
    endforeach()
    # Link options precede the objects on the command line; the libraries follow them.
    target_link_options(${target} PRIVATE LINKER:--whole-archive ${archives}
                        LINKER:--no-whole-archive)
  endif()
  # GoogleTest and Eigen parsed once for every test program (tests/CMakeLists.txt,
  # dynid_test_pch).
  target_precompile_headers(${target} REUSE_FROM dynid_test_pch)
  # The whole module in one batch (0: no limit; CMake's default is 8).
  set_target_properties(${target} PROPERTIES UNITY_BUILD_BATCH_SIZE 0
                                             RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/tests)
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
  gtest_discover_tests(${target} TEST_PREFIX "${prefix}." DISCOVERY_TIMEOUT 60
                       PROPERTIES RUN_SERIAL ${serial} ENVIRONMENT "${environment}")
endfunction()
