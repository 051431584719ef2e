# CTest Valgrind: SceneGen's tiny scene (64x48, 3 frames) synthesized by ViewSyn under valgrind's
# memcheck, on the general and the 1D path: no memcheck error (an invalid read or write, a use of an
# undefined value, a leak of definitely lost memory: exit 1 through --error-exitcode), and the output
# the same bytes as the same run without valgrind (valgrind's CPU has no AVX-512, so the kernels of a
# lower x86-64 level run there: the runtime-dispatch build's claim that every level gives the same
# bits, tested once more; a pinned x86-64-v4 build cannot run under valgrind 3.19 at all).
# Run as: cmake -DVALGRIND=... -DBIN_DIR=... -DWORK_DIR=... -P RunUnderValgrind.cmake
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")
execute_process(COMMAND "${BIN_DIR}/SceneGen" Scene=tiny "OutputFolder=${WORK_DIR}/scene"
                RESULT_VARIABLE result OUTPUT_QUIET ERROR_VARIABLE errors)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "SceneGen failed (${result}): ${errors}")
endif()
set(config "${WORK_DIR}/scene/viewsyn_cam1.cfg")
if(NOT EXISTS "${config}")
  message(FATAL_ERROR "SceneGen wrote no ${config}")
endif()
foreach(mode 0 1)
  set(native "${WORK_DIR}/native_${mode}.yuv")
  set(checked "${WORK_DIR}/valgrind_${mode}.yuv")
  execute_process(COMMAND "${BIN_DIR}/ViewSyn" "${config}" "OutputVirtualViewImageName=${native}" SynthesisMode=${mode}
                  RESULT_VARIABLE result OUTPUT_QUIET ERROR_VARIABLE errors)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "ViewSyn SynthesisMode=${mode} failed (${result}): ${errors}")
  endif()
  execute_process(COMMAND "${VALGRIND}" --error-exitcode=1 --leak-check=full --errors-for-leak-kinds=definite
                          "${BIN_DIR}/ViewSyn" "${config}" "OutputVirtualViewImageName=${checked}" SynthesisMode=${mode}
                  RESULT_VARIABLE result OUTPUT_QUIET ERROR_VARIABLE report)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "ViewSyn SynthesisMode=${mode} under valgrind exited with ${result}:\n${report}")
  endif()
  file(MD5 "${native}" native_md5)
  file(MD5 "${checked}" checked_md5)
  if(NOT native_md5 STREQUAL checked_md5)
    message(FATAL_ERROR "SynthesisMode=${mode}: the output under valgrind (${checked_md5}) differs from the native run's (${native_md5})")
  endif()
  message(STATUS "SynthesisMode=${mode}: no memcheck error, output equal to the native run's (${native_md5})")
endforeach()
