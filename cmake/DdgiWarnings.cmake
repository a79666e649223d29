# Warnings as errors on our code only; third-party headers come in as SYSTEM includes.
function(ddgi_target_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor
                                           -Wno-missing-field-initializers)
  if(DDGI_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()
