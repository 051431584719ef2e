target_link_libraries(SynthBench PRIVATE vssynth vsscene)
