target_link_libraries(ViewSyn PRIVATE vssynth)
# The C++ runtime linked in: a one-frame run is a few tens of milliseconds, of which the loader's
# relocations and symbol look-ups in libstdc++.so took about 0.5 to 1 ms (`ViewSyn --version`, perf
# stat task-clock, 1.2-1.8 ms -> 0.8-0.95 ms; doc/speed.md). glibc stays shared (valgrind's memcheck
# replaces its malloc; a sanitizer build keeps the shared runtime its allocator expects).
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND NOT VS_SANITIZE)
  target_link_options(ViewSyn PRIVATE -static-libstdc++ -static-libgcc)
endif()
