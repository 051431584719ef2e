target_link_libraries(ViewSyn PRIVATE vssynth)
