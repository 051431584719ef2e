# CTest: CITATION.cff states the project version of CMakeLists.txt and the licence LICENSE holds.
# Run as: cmake -DSOURCE_DIR=... -DVERSION=... -P CheckCitation.cmake
file(STRINGS "${SOURCE_DIR}/CITATION.cff" version_line REGEX "^version:")
if(NOT version_line MATCHES "^version: *\"?([^\"]+)\"? *$")
  message(FATAL_ERROR "CITATION.cff: no top-level 'version:' line")
endif()
if(NOT CMAKE_MATCH_1 STREQUAL VERSION)
  message(FATAL_ERROR "CITATION.cff: version '${CMAKE_MATCH_1}', but CMakeLists.txt's project version is '${VERSION}'")
endif()
file(STRINGS "${SOURCE_DIR}/CITATION.cff" license_line REGEX "^license:")
file(STRINGS "${SOURCE_DIR}/LICENSE" license_title LIMIT_COUNT 1)
if(NOT license_line MATCHES "BSD-3-Clause" OR NOT license_title MATCHES "^BSD 3-Clause License")
  message(FATAL_ERROR "CITATION.cff says '${license_line}', LICENSE starts '${license_title}': expected BSD-3-Clause in both")
endif()
