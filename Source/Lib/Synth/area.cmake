# vssynth: ViewSyn's renderer; it receives the plan (vsplan) and decides nothing itself.
# No OpenCV: the thread pool is our own (Synth/Parallel.h); only the tests link OpenCV, to compare the
# inpainting with cv::inpaint (Test/CMakeLists.txt).
target_link_libraries(vssynth PUBLIC vsplan vspipeline)
# The embeddable API (ViewSynthesis/Embed.h): ViewSyn's synthesis on cameras and frames in memory.
target_sources(vssynth PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/ViewSynthesis/Embed.cpp)
# The kernels (Synth/Kernels: the rasteriser, QuadRow.cpp, and the row loops of the warps and the
# blend, Rows.cpp) once per x86-64 level (VS_KERNEL_LEVELS, CMakeLists.txt), each level in a namespace
# of its own (vs::v1 .. vs::v4), into vssynth; KernelDispatch.cpp picks one level at start. In a pinned
# build the one level is the build's own (its -march applies to every file).
set(vs_kernel_defines)
foreach(level ${VS_KERNEL_LEVELS})
  add_library(vskernels_v${level} OBJECT ${CMAKE_CURRENT_SOURCE_DIR}/Synth/Kernels/QuadRow.cpp
                                         ${CMAKE_CURRENT_SOURCE_DIR}/Synth/Kernels/Rows.cpp)
  target_include_directories(vskernels_v${level} PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
  target_compile_definitions(vskernels_v${level} PRIVATE VS_LEVEL_NS=v${level} VS_KERNEL_LEVEL=${level})
  if(VS_X86_64_LEVEL STREQUAL "dispatch" AND level GREATER 1)
    target_compile_options(vskernels_v${level} PRIVATE -march=x86-64-v${level})
  endif()
  target_sources(vssynth PRIVATE $<TARGET_OBJECTS:vskernels_v${level}>)
  list(APPEND vs_kernel_defines VS_KERNEL_LEVEL_${level})
endforeach()
set_source_files_properties(${CMAKE_CURRENT_SOURCE_DIR}/Synth/KernelDispatch.cpp PROPERTIES
                            COMPILE_DEFINITIONS "${vs_kernel_defines}")
