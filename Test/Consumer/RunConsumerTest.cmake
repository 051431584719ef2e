# CTest InstalledConsumer: installs this build into a scratch prefix, builds Test/Consumer against it
# (find_package(ViewSynthesis) only: no path into the source or build tree), renders SceneGen's tiny
# scene, and checks that the consumer's in-memory synthesis equals ViewSyn's output file byte for byte.
# Run as: cmake -DBUILD_DIR=... -DSOURCE_DIR=... -DBIN_DIR=... -DWORK_DIR=... -P RunConsumerTest.cmake
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE result OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT result EQUAL 0)
    string(REPLACE ";" " " command "${ARGN}")
    message(FATAL_ERROR "failed (${result}): ${command}\n${out}\n${err}")
  endif()
endfunction()

file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)
run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
foreach(installed bin/ViewSyn bin/YuvPsnr include/viewsynthesis/ViewSynthesis/Embed.h
        lib/cmake/ViewSynthesis/ViewSynthesisConfig.cmake share/doc/viewsynthesis/manual.md
        share/doc/viewsynthesis/LICENSE share/viewsynthesis/cfg/ViewSyn.cfg.template)
  if(NOT EXISTS ${prefix}/${installed})
    message(FATAL_ERROR "cmake --install did not install ${installed}")
  endif()
endforeach()

# The consumer, built as another project would build it (same compiler and build type as this build).
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/Test/Consumer -B ${WORK_DIR}/build -DCMAKE_PREFIX_PATH=${prefix}
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=${CXX_COMPILER})
run(${CMAKE_COMMAND} --build ${WORK_DIR}/build)

# The scene and ViewSyn's output from the installed ViewSyn.
set(scene ${WORK_DIR}/scene)
run(${BIN_DIR}/SceneGen SceneFile=${SOURCE_DIR}/cfg/scenes/tiny.scene OutputFolder=${scene} Threads=1)
run(${prefix}/bin/ViewSyn ${scene}/viewsyn_cam1.cfg OutputVirtualViewImageName=${WORK_DIR}/viewsyn.yuv Threads=1)

# The consumer on the same inputs: cameras, sizes and depth ranges from the config ViewSyn read.
file(STRINGS ${scene}/viewsyn_cam1.cfg lines)
foreach(line ${lines})
  if(line MATCHES "^([A-Za-z]+)[ \t]+([^ \t#]+)")
    set(key_${CMAKE_MATCH_1} ${CMAKE_MATCH_2})
  endif()
endforeach()
foreach(key SourceWidth SourceHeight TotalNumberOfFrames SynthesisMode LeftCameraName RightCameraName VirtualCameraName
        LeftNearestDepthValue LeftFarthestDepthValue RightNearestDepthValue RightFarthestDepthValue)
  if(NOT DEFINED key_${key})
    message(FATAL_ERROR "${scene}/viewsyn_cam1.cfg: no ${key}")
  endif()
endforeach()
function(input key out)
  if(IS_ABSOLUTE ${key_${key}})
    set(${out} ${key_${key}} PARENT_SCOPE)
  else()
    set(${out} ${scene}/${key_${key}} PARENT_SCOPE)
  endif()
endfunction()
input(CameraParameterFile cameras)
input(LeftViewImageName leftTexture)
input(LeftDepthMapName leftDepth)
input(RightViewImageName rightTexture)
input(RightDepthMapName rightDepth)
run(${WORK_DIR}/build/EmbedConsumer ${cameras} ${key_SourceWidth} ${key_SourceHeight} ${key_TotalNumberOfFrames}
    ${key_VirtualCameraName} ${WORK_DIR}/consumer.yuv
    ${key_LeftCameraName} ${key_LeftNearestDepthValue} ${key_LeftFarthestDepthValue} ${leftTexture} ${leftDepth}
    ${key_RightCameraName} ${key_RightNearestDepthValue} ${key_RightFarthestDepthValue} ${rightTexture} ${rightDepth}
    SynthesisMode=${key_SynthesisMode})
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${WORK_DIR}/viewsyn.yuv ${WORK_DIR}/consumer.yuv
                RESULT_VARIABLE differ)
file(SIZE ${WORK_DIR}/viewsyn.yuv bytes)
if(NOT differ EQUAL 0 OR bytes EQUAL 0)
  message(FATAL_ERROR "the consumer's in-memory synthesis differs from ViewSyn's output (${bytes} bytes)")
endif()
message(STATUS "consumer output equals ViewSyn's: ${bytes} bytes")
