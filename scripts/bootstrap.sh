#!/usr/bin/env bash
# Makes sure the build's system pieces are there, on a fresh machine with only Rust, Python 3 and
# pip: cmake >= 3.26 for the bundled static HDF5 build (Debian's apt cmake 3.25 is too old), taken
# from PyPI into the project-local tool environment .tools/. Source this file; it extends PATH.
# With BOOTSTRAP_CVODE=1 it also makes sure of libclang (Debian's libclang-dev, by apt-get as
# root), which bindgen needs to build the optional `cvode` feature (sundials-sys); without it
# nothing of that is checked or installed.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
tools="$root/.tools"

cmake_ok() {
  command -v cmake >/dev/null 2>&1 || return 1
  local v
  v=$(cmake --version | head -n1 | sed -E 's/[^0-9]*([0-9]+)\.([0-9]+).*/\1 \2/')
  set -- $v
  [ "$1" -gt 3 ] || { [ "$1" -eq 3 ] && [ "$2" -ge 26 ]; }
}

export PATH="$tools/bin:$PATH"
if ! cmake_ok; then
  echo "bootstrap: installing cmake >= 3.26 from PyPI into .tools/" >&2
  if [ ! -x "$tools/bin/pip" ]; then
    python3 -m venv "$tools" >&2 || { rm -rf "$tools"; python3 -m pip install --quiet --target "$tools/lib" 'cmake>=3.26' >&2; }
  fi
  if [ -x "$tools/bin/pip" ]; then
    "$tools/bin/pip" install --quiet --disable-pip-version-check 'cmake>=3.26' >&2
  else
    mkdir -p "$tools/bin"
    printf '#!/bin/sh\nPYTHONPATH="%s/lib" exec python3 -c "import cmake,sys; sys.argv[0]=\\"cmake\\"; sys.exit(cmake.cmake())" "$@"\n' "$tools" > "$tools/bin/cmake"
    chmod +x "$tools/bin/cmake"
  fi
  cmake_ok || { echo "bootstrap: could not get cmake >= 3.26" >&2; exit 1; }
fi

if [ "${BOOTSTRAP_CVODE:-0}" = 1 ]; then
  libclang_ok() {
    ls /usr/lib/llvm-*/lib/libclang.so* /usr/lib/x86_64-linux-gnu/libclang-*.so* >/dev/null 2>&1 &&
      ls /usr/lib/llvm-*/lib/clang/*/include/stddef.h >/dev/null 2>&1
  }
  if ! libclang_ok; then
    echo "bootstrap: installing libclang-dev (apt) for the cvode feature's bindgen" >&2
    apt-get update -qq >&2 && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libclang-dev >&2
    libclang_ok || { echo "bootstrap: could not get libclang (the cvode feature needs it)" >&2; exit 1; }
  fi
fi
