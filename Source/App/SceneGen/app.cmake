target_link_libraries(SceneGen PRIVATE vsscene)
