# Warnings (errors with VDTNAV_WERROR) and sanitizers for vdtnav's own targets only.
function(vdtnav_target_options target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic
                         $<$<BOOL:${VDTNAV_WERROR}>:-Werror>)
  if(VDTNAV_SANITIZE)
    target_compile_options(${target} PRIVATE -fsanitize=address,undefined -fno-omit-frame-pointer
                           -fno-sanitize-recover=undefined)
    target_link_options(${target} PRIVATE -fsanitize=address,undefined)
  endif()
endfunction()
