# Included by the top-level CMakeLists.txt when ARTEMIS_FUZZ is ON, before any module is added, so
# that every library of the tree (the parsers above all) is compiled with libFuzzer's coverage
# instrumentation and with AddressSanitizer + UndefinedBehaviorSanitizer. Only the fuzz targets
# themselves link libFuzzer (-fsanitize=fuzzer, fuzz/CMakeLists.txt). See fuzz/CMakeLists.txt.
if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
  message(FATAL_ERROR "ARTEMIS_FUZZ needs clang (libFuzzer): configure a separate tree with "
                      "CXX=clang++ (make fuzz does), not ${CMAKE_CXX_COMPILER_ID}")
endif()
if(ARTEMIS_SANITIZE)
  message(FATAL_ERROR "ARTEMIS_FUZZ sets its own sanitizers: leave ARTEMIS_SANITIZE OFF in a fuzz tree")
endif()
add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=all
                    -fno-omit-frame-pointer -g)
# Executables of the tree other than the fuzz targets (the CLI, tests when enabled) link the
# sanitizer runtimes; the coverage callbacks they would call are no-ops there.
add_link_options(-fsanitize=address,undefined)
# The smoke tests of fuzz/ (ctest --test-dir build-fuzz) need a CTestTestfile at the tree's root.
enable_testing()
