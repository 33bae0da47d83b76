# The consumer test, run as `cmake -P` (see tests/CMakeLists.txt):
#   1. cmake --install BUILD_DIR into WORK_DIR/prefix (component sdk: the package's files),
#   2. configure this folder's project against it (-DCMAKE_PREFIX_PATH) and build it,
#   3. check that the consumer compiled without LibTorch headers and found the package there,
#   4. run it on the tiny bundle in DATA_DIR with the installed configs and check what it prints.
foreach(var BUILD_DIR SOURCE_DIR WORK_DIR DATA_DIR GENERATOR CXX_COMPILER MOTIONFORK_SOURCE_DIR)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "run_consumer_test.cmake: pass -D${var}=...")
  endif()
endforeach()

function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} failed (${rc}):\n${ARGN}\n${out}\n${err}")
  endif()
  set(output "${out}" PARENT_SCOPE)
endfunction()

string(TIMESTAMP start "%s")
file(REMOVE_RECURSE "${WORK_DIR}")
set(prefix "${WORK_DIR}/prefix")
run("cmake --install" ${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${prefix}" --component sdk)
foreach(f include/motionfork/motionfork.h share/motionfork/configs/constraints/bandai.yaml
          lib/cmake/motionfork/motionforkConfig.cmake)
  if(NOT EXISTS "${prefix}/${f}")
    message(FATAL_ERROR "not installed: ${prefix}/${f}")
  endif()
endforeach()

run("configuring the consumer" ${CMAKE_COMMAND} -S "${SOURCE_DIR}" -B "${WORK_DIR}/build"
    -G "${GENERATOR}" -DCMAKE_CXX_COMPILER=${CXX_COMPILER} -DCMAKE_BUILD_TYPE=Release
    -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_EXPORT_COMPILE_COMMANDS=ON)
file(STRINGS "${WORK_DIR}/build/CMakeCache.txt" found REGEX "^motionfork_DIR:")
if(NOT found MATCHES "=${prefix}/")
  message(FATAL_ERROR "the consumer found motionfork elsewhere: ${found}")
endif()
run("building the consumer" ${CMAKE_COMMAND} --build "${WORK_DIR}/build")
file(READ "${WORK_DIR}/build/compile_commands.json" commands)
string(FIND "${commands}" "${MOTIONFORK_SOURCE_DIR}/src" internal)
if(commands MATCHES "torch|eigen3" OR internal GREATER_EQUAL 0)
  message(FATAL_ERROR "the consumer compiled with internal or LibTorch headers:\n${commands}")
endif()

run("running the consumer" ${CMAKE_COMMAND} -E env
    MOTIONFORK_CONFIG_DIR=${prefix}/share/motionfork/configs
    "${WORK_DIR}/build/consumer" "${DATA_DIR}/bundle" "${DATA_DIR}/history.csv")
message(STATUS "consumer output:\n${output}")
foreach(line "config_dir: ${prefix}/share/motionfork/configs" "constraints: bandai" "joints: 17"
             "first part: legs" "futures: 4 x 10 frames x 17 joints" "fixed part identical: yes")
  string(FIND "${output}" "${line}\n" at)
  if(at LESS 0)
    message(FATAL_ERROR "expected the line '${line}' in the consumer's output")
  endif()
endforeach()
if(NOT output MATCHES "checked: [0-4] valid of 4\n")
  message(FATAL_ERROR "expected 'checked: N valid of 4' in the consumer's output")
endif()
string(TIMESTAMP end "%s")
math(EXPR seconds "${end} - ${start}")
message(STATUS "consumer test: install, configure, build and run took ${seconds} s")
