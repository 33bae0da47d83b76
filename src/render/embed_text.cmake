# Turns a text file into a C++ header holding it as a NUL-terminated char array, so templates
# (viewer.html) stay files of their own instead of string literals in C++.
#   cmake -DINPUT=file -DOUTPUT=header.h -DNAME=kSymbol -P embed_text.cmake
file(READ "${INPUT}" hex HEX)
string(REGEX REPLACE "([0-9a-f][0-9a-f])" "'\\\\x\\1'," bytes "${hex}")
# 16 bytes a line keeps the generated header readable by editors.
string(REGEX REPLACE "(('[^']*',){16})" "\\1\n  " bytes "${bytes}")
get_filename_component(source "${INPUT}" NAME)
file(WRITE "${OUTPUT}.tmp"
  "// Generated from ${source} by embed_text.cmake; do not edit.\n#pragma once\n\n"
  "inline constexpr char ${NAME}[] = {\n  ${bytes}'\\0'};\n")
file(RENAME "${OUTPUT}.tmp" "${OUTPUT}")
