# glint_header_check(module library): compiles each public header of `library` alone. One
# translation unit per header under <module>/include, generated into the build folder, includes
# that header (twice, for its include guard) and nothing else; they form the OBJECT library
# glint_<module>_header_check, built with the rest (so `make test` builds it), which sees only
# the library's public include path. A header that does not include what it uses, or that needs
# a private header, fails the build (docs/architecture.md, "Public headers").
function(glint_header_check module library)
  # The instrumented build (make test-sanitize) would compile the same checks again: make test
  # already has.
  if(GLINT_SANITIZE)
    return()
  endif()
  set(include_dir ${CMAKE_CURRENT_SOURCE_DIR}/include)
  file(GLOB_RECURSE headers CONFIGURE_DEPENDS RELATIVE ${include_dir} ${include_dir}/*.h)
  set(sources)
  foreach(header ${headers})
    string(MAKE_C_IDENTIFIER ${header} name)
    set(source ${CMAKE_CURRENT_BINARY_DIR}/header_check/${name}.cpp)
    # Written only when the content changes, so a reconfigure rebuilds nothing.
    file(CONFIGURE OUTPUT ${source} CONTENT "#include \"${header}\"\n#include \"${header}\"\n")
    list(APPEND sources ${source})
  endforeach()
  # Drop the translation units of headers that were removed or moved.
  file(GLOB stale ${CMAKE_CURRENT_BINARY_DIR}/header_check/*.cpp)
  if(sources)
    list(REMOVE_ITEM stale ${sources})
  endif()
  if(stale)
    file(REMOVE ${stale})
  endif()
  set(target glint_${module}_header_check)
  add_library(${target} OBJECT ${sources})
  target_link_libraries(${target} PRIVATE ${library})
  glint_warnings(${target})
  if(NOT TARGET glint_header_check)
    add_custom_target(glint_header_check)
  endif()
  add_dependencies(glint_header_check ${target})
endfunction()
