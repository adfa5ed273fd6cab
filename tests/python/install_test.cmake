# Installs the build into PREFIX and imports dynid from PREFIX/MODULE_DIR, with no PYTHONPATH
# into the build tree.
file(REMOVE_RECURSE "${PREFIX}")
execute_process(COMMAND ${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${PREFIX}"
                RESULT_VARIABLE rc OUTPUT_QUIET)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cmake --install failed: ${rc}")
endif()
file(GLOB module "${PREFIX}/${MODULE_DIR}/dynid*.so")
if(NOT module)
  message(FATAL_ERROR "no dynid module under ${PREFIX}/${MODULE_DIR}")
endif()
# The type stubs beside it, when the build made them (python3-mypy present).
if(EXISTS "${BUILD_DIR}/python/dynid.pyi" AND NOT EXISTS "${PREFIX}/${MODULE_DIR}/dynid.pyi")
  message(FATAL_ERROR "the build made dynid.pyi but it is not installed beside the module")
endif()
execute_process(
  COMMAND ${CMAKE_COMMAND} -E env --unset=PYTHONPATH "PYTHONPATH=${PREFIX}/${MODULE_DIR}"
          ${PYTHON} -c "import dynid, numpy; m = dynid.load_model('puma560'); print(dynid.__file__, dynid.rnea(m, numpy.zeros(6), numpy.zeros(6), numpy.zeros(6))[1])"
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT out MATCHES "^${PREFIX}")
  message(FATAL_ERROR "importing the installed module failed (${rc}): ${out}${err}")
endif()
file(REMOVE_RECURSE "${PREFIX}")
