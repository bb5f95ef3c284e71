# Writes OUT: a C++ file defining artemis::embedded::SYMBOL() with the bytes of IN (as hex, so any
# content is safe).
file(READ ${IN} hex HEX)
string(LENGTH "${hex}" hex_length)
math(EXPR size "${hex_length} / 2")
string(REGEX REPLACE "([0-9a-f][0-9a-f])" "0x\\1," bytes "${hex}")
file(WRITE ${OUT} "// Generated from ${IN}; do not edit.\n#include <string_view>\nnamespace artemis::embedded {\n"
  "std::string_view ${SYMBOL}();\n"
  "namespace { const unsigned char k${SYMBOL}[] = {${bytes} 0}; }\n"
  "std::string_view ${SYMBOL}() { return {reinterpret_cast<const char*>(k${SYMBOL}), ${size}}; }\n"
  "}  // namespace artemis::embedded\n")
