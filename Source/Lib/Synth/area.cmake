# vssynth: ViewSyn's renderer; it receives the plan (vsplan) and decides nothing itself.
target_link_libraries(vssynth PUBLIC vsplan vspipeline ${OpenCV_LIBS})
target_include_directories(vssynth SYSTEM PUBLIC ${OpenCV_INCLUDE_DIRS})
# The embeddable API (ViewSynthesis/Embed.h): ViewSyn's synthesis on cameras and frames in memory.
target_sources(vssynth PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/ViewSynthesis/Embed.cpp)
