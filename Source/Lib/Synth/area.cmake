target_link_libraries(vssynth PUBLIC vspipeline ${OpenCV_LIBS})
target_include_directories(vssynth SYSTEM PUBLIC ${OpenCV_INCLUDE_DIRS})
