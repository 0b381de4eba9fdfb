# Warning set for every target of the project (not exported to plugin authors).
function(hapticd_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor
                                            -Wold-style-cast -Woverloaded-virtual)
  if(HAPTICD_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()
