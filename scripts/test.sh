#!/usr/bin/env bash
# Installs what is needed, checks the formatting, builds, and runs every test: the normal build, then the whole suite
# again under AddressSanitizer + UndefinedBehaviorSanitizer (LeakSanitizer included), the two-thread geometry tests
# under ThreadSanitizer, bounded fuzz runs, and the container image built and probed. Exit status 0 only when all pass.
#   SURFACED_SKIP_SANITIZE=1 scripts/test.sh   skip the sanitizer pass (quicker local runs; CI runs it)
#   SURFACED_SKIP_TSAN=1                       skip the ThreadSanitizer pass over the two-thread geometry tests
#   SURFACED_SKIP_FUZZ=1                       skip the bounded libFuzzer runs (scripts/fuzz.sh, 12 s per target)
#   SURFACED_SKIP_CONTAINER=1                  skip the container image build + test (scripts/container-test.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
# ccache: hit across clones at different paths (CI clones afresh every run)
export CCACHE_BASEDIR="$PWD" CCACHE_NOHASHDIR=1
start=$(date +%s)
scripts/install-deps.sh
scripts/check-format.sh
scripts/build.sh
echo "== build done in $(( $(date +%s) - start )) s"
(cd build && ctest --output-on-failure -j"$(nproc)" --timeout 600)
echo "== tests done in $(( $(date +%s) - start )) s"

if [ "${SURFACED_SKIP_SANITIZE:-0}" != 1 ]; then
  # -O1 -g1: about half the compile time of -O2 -g (this tree is always built from scratch on a fresh machine), line
  # numbers in sanitizer reports kept
  cmake -S . -B build-sanitize -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSURFACED_SANITIZE=ON \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
    -DSURFACED_BUILD_BENCH=OFF -DSURFACED_WERROR=ON >/dev/null
  cmake --build build-sanitize -j"$(nproc)"
  echo "== sanitizer build done in $(( $(date +%s) - start )) s"
  (cd build-sanitize && ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
     ctest --output-on-failure -j"$(nproc)" --timeout 900 -LE browser)   # the browser tests run in the first pass
  echo "== sanitizer tests done in $(( $(date +%s) - start )) s"
fi

if [ "${SURFACED_SKIP_TSAN:-0}" != 1 ]; then
  # ThreadSanitizer over the tests that run geometry on two threads (subdivision and QEM simplification with threads 2,
  # the simplifier's block pool, Poisson reconstruction with threads 2): only those tests are built in this tree
  cmake -S . -B build-tsan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS="-fsanitize=thread" \
    -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=thread" -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
    -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DSURFACED_BUILD_BENCH=OFF -DSURFACED_WERROR=ON >/dev/null
  cmake --build build-tsan -j"$(nproc)" --target geometry_tests reconstruct_tests
  TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1 \
    build-tsan/tests/geometry_tests --gtest_filter='*Thread*:Qem.IsDeterministicOnReusedMemory' --gtest_brief=1
  TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1 \
    build-tsan/tests/reconstruct_tests --gtest_filter='*Thread*' --gtest_brief=1
  echo "== thread sanitizer done in $(( $(date +%s) - start )) s"
fi

if [ "${SURFACED_SKIP_FUZZ:-0}" != 1 ]; then
  scripts/fuzz.sh "${SURFACED_FUZZ_SECONDS:-12}"
  echo "== fuzz runs done in $(( $(date +%s) - start )) s"
fi
if [ "${SURFACED_SKIP_CONTAINER:-0}" != 1 ]; then
  scripts/container-test.sh   # prints "== container test done in N s"
fi
