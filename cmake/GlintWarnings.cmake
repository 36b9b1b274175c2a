# glint_warnings(target): Glint's own code builds with warnings as errors.
function(glint_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Werror)
endfunction()
