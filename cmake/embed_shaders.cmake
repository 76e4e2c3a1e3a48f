# Writes OUTPUT: a C++ file that maps each shader's path under SHADER_DIR to its text, so the library needs
# no files at run time. Run as `cmake -DSHADER_DIR=... -DOUTPUT=... -P embed_shaders.cmake`.
file(GLOB_RECURSE shader_files RELATIVE "${SHADER_DIR}" "${SHADER_DIR}/*.glsl" "${SHADER_DIR}/*.vert"
     "${SHADER_DIR}/*.frag" "${SHADER_DIR}/*.geom" "${SHADER_DIR}/*.tesc" "${SHADER_DIR}/*.tese" "${SHADER_DIR}/*.comp")
list(SORT shader_files)
set(entries "")
foreach(file IN LISTS shader_files)
  file(READ "${SHADER_DIR}/${file}" text)
  string(APPEND entries "      {\"${file}\", R\"bounce_glsl(${text})bounce_glsl\"},\n")
endforeach()
set(content "// Generated from shaders/ by cmake/embed_shaders.cmake. Do not edit.
#include <map>
#include <string>

namespace bounce::gl {

const std::map<std::string, std::string>& embedded_shaders() {
  static const std::map<std::string, std::string> shaders = {
${entries}  };
  return shaders;
}

}  // namespace bounce::gl
")
# Only touch the file when it changes, so unchanged shaders do not relink.
if(EXISTS "${OUTPUT}")
  file(READ "${OUTPUT}" old)
  if(old STREQUAL content)
    return()
  endif()
endif()
file(WRITE "${OUTPUT}" "${content}")
