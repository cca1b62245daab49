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

# The library's components and the CLI: unity build when VDTNAV_UNITY_BUILD (top CMakeLists).
function(vdtnav_unity_build target)
  if(VDTNAV_UNITY_BUILD)
    set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE 8)
  endif()
endfunction()

# The component libraries are position-independent code, so that the Python module (a shared
# object, python/) can link them; -fno-semantic-interposition keeps GCC inlining calls between
# the functions of one library as it does without -fPIC (nothing interposes them: they are linked
# statically).
function(vdtnav_library_options target)
  set_target_properties(${target} PROPERTIES POSITION_INDEPENDENT_CODE ON)
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    target_compile_options(${target} PRIVATE -fno-semantic-interposition)
  endif()
endfunction()
