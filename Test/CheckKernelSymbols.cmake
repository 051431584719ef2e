# CTest KernelSymbols_vN: a kernel object compiled for x86-64 level N (Source/Lib/Synth/Kernels) defines
# no symbol the linker could share with another file, such as an inline function or a template of a
# shared header compiled with N's instructions: each global or weak symbol it defines lies in vs::vN.
# Run as: cmake -DNM=... -DLEVEL_NS=v3 -DOBJECTS="a.o;b.o" -P CheckKernelSymbols.cmake
foreach(object ${OBJECTS})
  execute_process(COMMAND ${NM} -C --defined-only ${object} OUTPUT_VARIABLE symbols RESULT_VARIABLE result)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "${NM} failed on ${object}")
  endif()
  string(REPLACE "\n" ";" lines "${symbols}")
  set(count 0)
  foreach(line ${lines})
    # Upper-case types are global (T, D, R, B), W and V weak, u unique global: all may be shared.
    if(line MATCHES "^[0-9a-f]* ([TDRBWVu]) (.*)$")
      set(type ${CMAKE_MATCH_1})
      set(name "${CMAKE_MATCH_2}")
      math(EXPR count "${count} + 1")
      # AddressSanitizer adds an ODR indicator per global, named after the global's mangled name.
      string(LENGTH "${LEVEL_NS}" ns_length)
      if(name MATCHES "^__odr_asan\\._ZN2vs${ns_length}${LEVEL_NS}")
        continue()
      endif()
      # The pointer to the C++ runtime's exception personality routine, which every object with a
      # cleanup on an exception's path carries (here a sanitizer build's): data, the same in every
      # object, no instructions of any level.
      if(name STREQUAL "DW.ref.__gxx_personality_v0")
        continue()
      endif()
      # A function template's demangled name starts with its return type ("void vs::v4::f<...>(...)").
      if(NOT name MATCHES "^([^(<]* )?vs::${LEVEL_NS}::")
        message(FATAL_ERROR "${object}: '${name}' (${type}) is defined outside vs::${LEVEL_NS}")
      endif()
    endif()
  endforeach()
  if(count EQUAL 0)
    message(FATAL_ERROR "${object}: no global symbol in vs::${LEVEL_NS} (the kernels' table is missing)")
  endif()
endforeach()
