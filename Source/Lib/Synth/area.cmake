# vssynth: ViewSyn's renderer; it receives the plan (vsplan) and decides nothing itself.
# No OpenCV: the thread pool is our own (Synth/Parallel.h); only the tests link OpenCV, to compare the
# inpainting with cv::inpaint (Test/CMakeLists.txt).
target_link_libraries(vssynth PUBLIC vsplan vspipeline)
# The embeddable API (ViewSynthesis/Embed.h): ViewSyn's synthesis on cameras and frames in memory.
target_sources(vssynth PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/ViewSynthesis/Embed.cpp)
# The rasteriser's kernels once per x86-64 level (VS_KERNEL_LEVELS, CMakeLists.txt), each in a
# namespace of its own (vs::v1 .. vs::v4, see Synth/Raster.h), into vssynth; QuadRowDispatch.cpp picks
# one at start. In a pinned build the one level is the build's own (its -march applies to every file).
set(vs_kernel_defines)
foreach(level ${VS_KERNEL_LEVELS})
  add_library(vsquadrow_v${level} OBJECT ${CMAKE_CURRENT_SOURCE_DIR}/Synth/Kernels/QuadRow.cpp)
  target_include_directories(vsquadrow_v${level} PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
  target_compile_definitions(vsquadrow_v${level} PRIVATE VS_LEVEL_NS=v${level} VS_KERNEL_LEVEL=${level})
  if(VS_X86_64_LEVEL STREQUAL "dispatch" AND level GREATER 1)
    target_compile_options(vsquadrow_v${level} PRIVATE -march=x86-64-v${level})
  endif()
  target_sources(vssynth PRIVATE $<TARGET_OBJECTS:vsquadrow_v${level}>)
  list(APPEND vs_kernel_defines VS_KERNEL_LEVEL_${level})
endforeach()
set_source_files_properties(${CMAKE_CURRENT_SOURCE_DIR}/Synth/QuadRowDispatch.cpp PROPERTIES
                            COMPILE_DEFINITIONS "${vs_kernel_defines}")
