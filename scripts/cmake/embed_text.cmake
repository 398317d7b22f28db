# Writes a text file into a C++ source as one raw string literal, at build time:
#   cmake -DINPUT=FILE -DOUTPUT=FILE.cpp -DNAME=kName -DNAMESPACE=ns -P embed_text.cmake
# (mechgen view's page template: mechgen then needs no file of the source tree at run time).
file(READ "${INPUT}" text)
string(FIND "${text}" ")embedded_text\"" clash)
if(NOT clash EQUAL -1)
  message(FATAL_ERROR "${INPUT} contains the raw string's end marker )embedded_text\"")
endif()
file(WRITE "${OUTPUT}.tmp"
     "// Generated at build time from ${INPUT} by scripts/cmake/embed_text.cmake: do not edit.\n"
     "namespace ${NAMESPACE} {\n"
     "extern const char* const ${NAME};\n"
     "const char* const ${NAME} = R\"embedded_text(${text})embedded_text\";\n"
     "}  // namespace ${NAMESPACE}\n")
file(COPY_FILE "${OUTPUT}.tmp" "${OUTPUT}" ONLY_IF_DIFFERENT)
file(REMOVE "${OUTPUT}.tmp")
