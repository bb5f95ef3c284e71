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
  if(NOT ARTEMIS_UNITY_LIBRARIES)
    set_target_properties(${target} PROPERTIES UNITY_BUILD OFF)
  endif()
  set_property(GLOBAL APPEND PROPERTY ARTEMIS_MODULES ${target})
  install(DIRECTORY include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endfunction()
