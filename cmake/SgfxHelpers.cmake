# Warnings for sgfx's own code (third-party code is compiled without them).
function(sgfx_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor)
  # GCC 12 reports -Wrestrict false positives inside libstdc++ string concatenation (GCC bug 105329).
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
    target_compile_options(${target} PRIVATE -Wno-restrict)
  endif()
  if(SGFX_SANITIZE)
    # GCC's -Wmaybe-uninitialized misfires inside libstdc++ (<regex>, std::function) under
    # -fsanitize instrumentation; the normal build keeps the warning.
    target_compile_options(${target} PRIVATE -Wno-maybe-uninitialized)
  endif()
  if(SGFX_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

# Embeds text files into a generated .cpp: `std::string_view NAMESPACE::embedded(name)`.
function(sgfx_embed_files target namespace)
  set(out ${CMAKE_CURRENT_BINARY_DIR}/${target}_embedded.cpp)
  add_custom_command(OUTPUT ${out}
    COMMAND ${CMAKE_COMMAND} -DOUT=${out} -DNAMESPACE=${namespace} "-DFILES=${ARGN}"
            -P ${PROJECT_SOURCE_DIR}/cmake/EmbedFiles.cmake
    DEPENDS ${ARGN} ${PROJECT_SOURCE_DIR}/cmake/EmbedFiles.cmake
    COMMENT "Embedding shaders for ${target}" VERBATIM)
  target_sources(${target} PRIVATE ${out})
endfunction()

# What every sgfx library shares: hidden symbols but those the public headers mark SGFX_API
# (sgfx/Export.h), the SONAME and version from project(VERSION), and the warnings.
function(sgfx_library target)
  set_target_properties(${target} PROPERTIES
    CXX_VISIBILITY_PRESET hidden C_VISIBILITY_PRESET hidden VISIBILITY_INLINES_HIDDEN ON
    VERSION ${PROJECT_VERSION} SOVERSION ${PROJECT_VERSION_MAJOR}
    OUTPUT_NAME ${target})
  sgfx_warnings(${target})
endfunction()
