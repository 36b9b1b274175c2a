# ctest driver: install Glint from the build tree into a temporary prefix, configure and build
# the consumer project against it, run it on a tiny scene and check the EXR it writes.
# Variables: GLINT_BUILD_DIR, CONSUMER_DIR, WORK_DIR, SCENE, GENERATOR.
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})
function(run_step what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "${what} failed (${code}):\n${out}\n${err}")
  endif()
  message(STATUS "${what}: ok\n${out}")
endfunction()
run_step("install" ${CMAKE_COMMAND} --install ${GLINT_BUILD_DIR} --prefix ${WORK_DIR}/prefix)
run_step("configure consumer" ${CMAKE_COMMAND} -S ${CONSUMER_DIR} -B ${WORK_DIR}/build
         -G ${GENERATOR} -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix)
run_step("build consumer" ${CMAKE_COMMAND} --build ${WORK_DIR}/build)
run_step("run consumer" ${WORK_DIR}/build/glint-consumer ${SCENE} ${WORK_DIR}/out.exr)
if(NOT EXISTS ${WORK_DIR}/out.exr)
  message(FATAL_ERROR "the consumer wrote no EXR")
endif()
run_step("read the EXR back" ${GLINT_BUILD_DIR}/bin/glint-image info ${WORK_DIR}/out.exr)
file(REMOVE_RECURSE ${WORK_DIR})
