# Installs the build tree to a temporary prefix, moves the prefix elsewhere (a relocatable install
# names no path of the machine that built it), then configures, builds and runs the consumer
# project against the moved copy. Arguments: -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=...
file(REMOVE_RECURSE "${WORK_DIR}")
execute_process(COMMAND "${CMAKE_COMMAND}" --install "${BUILD_DIR}" --prefix "${WORK_DIR}/prefix"
                RESULT_VARIABLE rc OUTPUT_QUIET)
if(rc)
  message(FATAL_ERROR "cmake --install failed")
endif()
# Public headers under include/dynid/<module>/, internal ones not installed at all.
foreach(header core/rnea.hpp core/drive_terms.hpp search/gc_problem.hpp search/refinement/options.hpp
               analysis/estimation/pipeline.hpp identifiability/base_estimate.hpp)
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
# The shell completion and the man pages, generated from the commands' option tables.
foreach(file share/bash-completion/completions/dynid share/zsh/site-functions/_dynid
             share/man/man1/dynid.1 share/man/man1/dynid-identify.1 share/man/man1/dynid-model-export.1)
  if(NOT EXISTS "${WORK_DIR}/prefix/${file}")
    message(FATAL_ERROR "${file} was not installed")
  endif()
endforeach()
# No absolute path of this machine's libraries or of the prefix in the exported targets.
file(GLOB exported "${WORK_DIR}/prefix/lib/cmake/dynid/dynidTargets*.cmake")
foreach(file ${exported})
  file(READ "${file}" text)
  foreach(absolute "${WORK_DIR}" "/usr/lib/" "/usr/local/lib/")
    string(FIND "${text}" "${absolute}" at)
    if(NOT at EQUAL -1)
      message(FATAL_ERROR "${file} names the absolute path ${absolute}: not relocatable")
    endif()
  endforeach()
endforeach()
file(RENAME "${WORK_DIR}/prefix" "${WORK_DIR}/moved")
execute_process(COMMAND "${CMAKE_COMMAND}" -S "${SOURCE_DIR}" -B "${WORK_DIR}/build"
                        -DCMAKE_PREFIX_PATH=${WORK_DIR}/moved -DCMAKE_BUILD_TYPE=Release
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
