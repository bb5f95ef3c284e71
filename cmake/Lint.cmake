# `cmake --build <dir> --target lint`: clang-format check and clang-tidy over the project's sources.
find_program(CLANG_FORMAT_PROGRAM NAMES clang-format clang-format-14)
find_program(CLANG_TIDY_PROGRAM NAMES clang-tidy clang-tidy-14)
file(GLOB_RECURSE artemis_lint_sources CONFIGURE_DEPENDS
     ${PROJECT_SOURCE_DIR}/src/*.cpp ${PROJECT_SOURCE_DIR}/src/*.hpp
     ${PROJECT_SOURCE_DIR}/apps/*.cpp ${PROJECT_SOURCE_DIR}/apps/*.hpp
     ${PROJECT_SOURCE_DIR}/tests/*.cpp ${PROJECT_SOURCE_DIR}/tests/*.hpp)
file(GLOB_RECURSE artemis_tidy_sources CONFIGURE_DEPENDS
     ${PROJECT_SOURCE_DIR}/src/*.cpp ${PROJECT_SOURCE_DIR}/apps/*.cpp)
set(lint_commands)
if(CLANG_FORMAT_PROGRAM)
  list(APPEND lint_commands COMMAND ${CLANG_FORMAT_PROGRAM} --dry-run --Werror ${artemis_lint_sources})
endif()
if(CLANG_TIDY_PROGRAM)
  list(APPEND lint_commands COMMAND ${CLANG_TIDY_PROGRAM} -p ${PROJECT_BINARY_DIR} --quiet
       ${artemis_tidy_sources})
endif()
if(lint_commands)
  add_custom_target(lint ${lint_commands} WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
                    COMMENT "clang-format and clang-tidy" VERBATIM)
  if(CLANG_FORMAT_PROGRAM)
    add_custom_target(format COMMAND ${CLANG_FORMAT_PROGRAM} -i ${artemis_lint_sources}
                      WORKING_DIRECTORY ${PROJECT_SOURCE_DIR} VERBATIM)
  endif()
endif()
