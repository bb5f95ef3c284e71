# Per-target compile settings shared by every ARTEMIS target.
function(artemis_target_settings target)
  target_compile_features(${target} PUBLIC cxx_std_20)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wconversion -Wshadow
                                           -Wnon-virtual-dtor -Wold-style-cast)
  if(ARTEMIS_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
  if(ARTEMIS_SANITIZE)
    target_compile_options(${target} PRIVATE -fsanitize=address,undefined -fno-omit-frame-pointer
                                             -fno-sanitize-recover=undefined)
    target_link_options(${target} PRIVATE -fsanitize=address,undefined)
  endif()
endfunction()

# artemis_add_module(<name> SOURCES ... PUBLIC_DEPS ... PRIVATE_DEPS ...)
# One library per module of DESIGN.md: target artemis_<name>, alias artemis::<name>,
# public headers under src/<name>/include/artemis/<name>/.
function(artemis_add_module name)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  set(target artemis_${name})
  add_library(${target} ${ARG_SOURCES})
  add_library(artemis::${name} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${name} OUTPUT_NAME artemis_${name}
                                             POSITION_INDEPENDENT_CODE ON)
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(${target} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  artemis_target_settings(${target})
  set_property(GLOBAL APPEND PROPERTY ARTEMIS_MODULES ${target})
  install(DIRECTORY include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endfunction()

# Under the sanitizers, executables whose own code does little (the program's argument parsing and
# command wiring, tests that run the program or check small cases) compile at -O0: about half the
# time of -O1 with CLI11's and GoogleTest's templates, while their run time is spent in the
# libraries, which keep the tree's -O1. Test bodies that loop over scans and meshes stay at -O1
# (at -O0 Eigen makes them ten times slower).
function(artemis_light_under_sanitizers target)
  if(ARTEMIS_SANITIZE)
    target_compile_options(${target} PRIVATE -O0)
  endif()
endfunction()
