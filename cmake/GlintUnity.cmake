# Unity builds for the targets of many small sources (docs/architecture.md, "Build time"): CMake
# concatenates up to `batch` sources of a target into one translation unit, so the headers they
# share are parsed once per batch and the inline and template code they share (the standard
# library, GoogleTest, nlohmann/json, CLI11) is generated once per batch, not once per source.
# Under ASan + UBSan, that generated code is most of a small source's compile time.
#
# Sources of one batch share a namespace scope: two of them must not define the same name in an
# anonymous namespace (or static) differently. A source that must stay alone is marked with
# SKIP_UNITY_BUILD_INCLUSION next to the target; a source with its own COMPILE_OPTIONS (the -O3
# kernels) is kept alone by CMake. Configure with -DGLINT_UNITY_BUILD=OFF to build every source
# alone, as an incremental edit-and-rebuild loop prefers (and to check that each source includes
# what it uses).
option(GLINT_UNITY_BUILD "Build the targets of many small sources as unity batches" ON)

# glint_unity(target batch): build `target` in unity batches of at most `batch` sources.
function(glint_unity target batch)
  if(GLINT_UNITY_BUILD)
    set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE ${batch})
    # GCC warns of a type with linkage that uses a type of an anonymous namespace unless both are
    # in the main file; in a batch every source is an included file, so it would warn of each
    # test fixture and pimpl (the types stay local to their batch, so nothing is shared). Clang
    # has no such warning (and would reject the option under -Werror).
    target_compile_options(${target} PRIVATE $<$<CXX_COMPILER_ID:GNU>:-Wno-subobject-linkage>)
  endif()
endfunction()

# glint_unity_skip(source...): sources (relative to the calling CMakeLists.txt) that are built
# alone, each with the reason next to the call.
function(glint_unity_skip)
  set_source_files_properties(${ARGN} PROPERTIES SKIP_UNITY_BUILD_INCLUSION ON)
endfunction()
