#!/usr/bin/env bash
# Configures and builds into build/ (RelWithDebInfo, warnings as errors, ccache when present).
#   scripts/build.sh                 everything (library, service, tests, benchmarks)
#   scripts/build.sh surfaced        only the named targets
set -euo pipefail
cd "$(dirname "$0")/.."
# ccache: hit across clones at different paths (CI clones afresh every run)
export CCACHE_BASEDIR="$PWD" CCACHE_NOHASHDIR=1
BUILD_DIR=${BUILD_DIR:-build}
if [ ! -f "$BUILD_DIR/build.ninja" ]; then
  cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSURFACED_WERROR=ON
fi
if [ $# -gt 0 ]; then
  cmake --build "$BUILD_DIR" -j"$(nproc)" --target "$@"
else
  cmake --build "$BUILD_DIR" -j"$(nproc)"
fi
