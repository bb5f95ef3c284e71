# artemis_embed_file(<target> <file> <symbol>): compiles <file>'s bytes into <target> as
#   std::string_view artemis::embedded::<symbol>();
# so that data files (vocabularies, alias tables) ship inside the program and need no install path,
# while staying plain data files in the repository. The build re-embeds when the file changes.
function(artemis_embed_file target file symbol)
  set(out ${CMAKE_CURRENT_BINARY_DIR}/embedded_${symbol}.cpp)
  add_custom_command(
    OUTPUT ${out}
    COMMAND ${CMAKE_COMMAND} -DIN=${file} -DOUT=${out} -DSYMBOL=${symbol} -P ${PROJECT_SOURCE_DIR}/cmake/EmbedFileScript.cmake
    DEPENDS ${file} ${PROJECT_SOURCE_DIR}/cmake/EmbedFileScript.cmake
    COMMENT "Embedding ${file}")
  target_sources(${target} PRIVATE ${out})
endfunction()
