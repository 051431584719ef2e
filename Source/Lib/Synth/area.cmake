# vssynth: ViewSyn's renderer; it receives the plan (vsplan) and decides nothing itself.
target_link_libraries(vssynth PUBLIC vsplan vspipeline ${OpenCV_LIBS})
target_include_directories(vssynth SYSTEM PUBLIC ${OpenCV_INCLUDE_DIRS})
