# Shared compile settings for every Dermis target.
function(dermis_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wconversion
                                           -Wno-sign-conversion)
  if(DERMIS_WARNINGS_AS_ERRORS)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
  if(DERMIS_SANITIZE)
    # -Og: the Debug build's -O0 ran the sanitized suite three times slower, and -O1 (what
    # AddressSanitizer's documentation advises) made this the longest build of CI; under GCC's
    # -Og the whole build takes about a quarter less compiler time and the tests run almost as
    # fast (docs/reliability.md, "Sanitizers in CI"). Assertions and debug information stay.
    # GCC 12 then warns -Wmaybe-uninitialized inside libstdc++'s <regex> (Catch's main) under
    # ASan, a false positive: that warning is checked by the other builds.
    target_compile_options(${target} PRIVATE -fsanitize=address,undefined -fno-omit-frame-pointer
                                             -fno-sanitize-recover=all -Og)
    if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
      target_compile_options(${target} PRIVATE -Wno-maybe-uninitialized)
    endif()
    target_link_options(${target} PRIVATE -fsanitize=address,undefined)
  endif()
  if(DERMIS_SANITIZE_THREAD)
    target_compile_options(${target} PRIVATE -fsanitize=thread -fno-omit-frame-pointer)
    target_link_options(${target} PRIVATE -fsanitize=thread)
  endif()
  if(DERMIS_BUILD_FUZZERS)
    # libFuzzer coverage, ASan and UBSan in every library the harnesses link (tests/fuzz).
    target_compile_options(${target} PRIVATE -fsanitize=fuzzer-no-link,address,undefined
                                             -fno-omit-frame-pointer -fno-sanitize-recover=all -g)
    target_link_options(${target} PRIVATE -fsanitize=address,undefined)
  endif()
endfunction()

# dermis_add_library(NAME ALIAS SOURCES...): a static library dermis_NAME with alias dermis::NAME.
function(dermis_add_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES" ${ARGN})
  add_library(dermis_${name} STATIC ${ARG_SOURCES})
  add_library(dermis::${name} ALIAS dermis_${name})
  target_include_directories(dermis_${name} PUBLIC
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/sdk/include>
    PRIVATE ${PROJECT_SOURCE_DIR}/sdk/src)
  dermis_set_warnings(dermis_${name})
endfunction()

function(dermis_add_executable name)
  cmake_parse_arguments(ARG "" "" "SOURCES" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  dermis_set_warnings(${name})
endfunction()
