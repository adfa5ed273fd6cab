# Installs the build tree to a temporary prefix, then configures, builds and runs the consumer
# project against it. Arguments: -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=...
file(REMOVE_RECURSE "${WORK_DIR}")
execute_process(COMMAND "${CMAKE_COMMAND}" --install "${BUILD_DIR}" --prefix "${WORK_DIR}/prefix"
                RESULT_VARIABLE rc OUTPUT_QUIET)
if(rc)
  message(FATAL_ERROR "cmake --install failed")
endif()
# Public headers under include/dynid/<module>/, internal ones not installed at all.
foreach(header core/rnea.hpp core/drive_terms.hpp search/gc_problem.hpp search/refinement/options.hpp
               analysis/pipeline.hpp identifiability/base_estimate.hpp)
  if(NOT EXISTS "${WORK_DIR}/prefix/include/dynid/${header}")
    message(FATAL_ERROR "the public header dynid/${header} was not installed")
  endif()
endforeach()
foreach(header search/gc_rollout.hpp search/refinement/uncertainty.hpp search/refinement/costs.hpp
               identifiability/tall_qr.hpp data/json_reader.hpp data/json_number.hpp)
  if(EXISTS "${WORK_DIR}/prefix/include/dynid/${header}")
    message(FATAL_ERROR "the internal header dynid/${header} was installed")
  endif()
endforeach()
if(EXISTS "${WORK_DIR}/prefix/include/core")
  message(FATAL_ERROR "headers were installed outside include/dynid/")
endif()
execute_process(COMMAND "${CMAKE_COMMAND}" -S "${SOURCE_DIR}" -B "${WORK_DIR}/build"
                        -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix -DCMAKE_BUILD_TYPE=Release
                RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "configuring the consumer with find_package(dynid) failed")
endif()
execute_process(COMMAND "${CMAKE_COMMAND}" --build "${WORK_DIR}/build" RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "building the consumer failed")
endif()
execute_process(COMMAND "${WORK_DIR}/build/consumer" RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "the consumer's PUMA gravity torque is wrong")
endif()
