#!/usr/bin/env bash
# Configures a sanitizer build of the project with clang:
#   tests/sanitize/configure.sh BUILD_DIR SANITIZERS     e.g. build-asan address,undefined
# address,undefined builds also get the fuzzers (the same instrumentation serves both); the
# client tools are left out. -O1 with line tables: stacks stay readable, runs stay fast enough.
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
build="$1"
sanitizers="$2"
fuzzers=OFF
[[ "${sanitizers}" == *address* ]] && fuzzers=ON
launcher=()
if command -v ccache >/dev/null; then
  launcher=(-DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
CC=clang CXX=clang++ cmake -S "${root}" -B "${build}" -G Ninja \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only" \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only" \
  -DDDGI_SANITIZE="${sanitizers}" -DDDGI_BUILD_FUZZERS="${fuzzers}" -DDDGI_BUILD_CLIENT=OFF \
  "${launcher[@]}" >/dev/null
