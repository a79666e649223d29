# Sanitizers and fuzzing instrumentation for every target that follows (the top-level
# CMakeLists includes this before adding any): DDGI_SANITIZE is the -fsanitize= list;
# DDGI_BUILD_FUZZERS adds libFuzzer's coverage instrumentation (clang only) and implies
# AddressSanitizer and UBSan, which the fuzzers rely on to turn memory errors into crashes.
if(DDGI_BUILD_FUZZERS)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "DDGI_BUILD_FUZZERS needs clang (configure with CC=clang CXX=clang++)")
  endif()
  if(NOT DDGI_SANITIZE)
    set(DDGI_SANITIZE "address,undefined")
  endif()
  if(NOT DDGI_SANITIZE MATCHES "address")
    message(FATAL_ERROR "DDGI_BUILD_FUZZERS needs DDGI_SANITIZE with address (got ${DDGI_SANITIZE})")
  endif()
  add_compile_options(-fsanitize=fuzzer-no-link)
endif()

if(DDGI_SANITIZE)
  # Stop at the first report (a test fails instead of printing and passing), keep frames for
  # readable stacks.
  add_compile_options(-fsanitize=${DDGI_SANITIZE} -fno-sanitize-recover=all
                      -fno-omit-frame-pointer)
  add_link_options(-fsanitize=${DDGI_SANITIZE})
endif()
