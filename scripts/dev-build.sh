#!/usr/bin/env bash
# Development build for several people (or agents) sharing this 2-core machine: one build tree, builds serialised
# by a lock so that two never run at once. Usage: scripts/dev-build.sh TARGET... (default: all)
set -euo pipefail
cd "$(dirname "$0")/.."
# ccache: the same keys as scripts/build.sh, so that dev builds warm the cache for CI clones too
export CCACHE_BASEDIR="$PWD" CCACHE_NOHASHDIR=1
targets=("$@"); [ ${#targets[@]} -gt 0 ] || targets=(all)
exec flock /tmp/surfaced-build.lock bash -c '
  [ -f build/build.ninja ] || cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSURFACED_WERROR=ON >/dev/null
  cmake --build build -j2 --target "$@"' _ "${targets[@]}"
