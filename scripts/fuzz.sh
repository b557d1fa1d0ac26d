#!/usr/bin/env bash
# Builds the libFuzzer targets (clang-14, -fsanitize=fuzzer,address,undefined) in build-fuzz/ and runs each one for
# SECONDS_PER_TARGET seconds (default 60), one after the other. Exit status 0 only when no target found anything.
#   scripts/fuzz.sh                    every target, 60 s each
#   scripts/fuzz.sh 600 fuzz_obj       one target, 10 minutes (long runs: the corpus grows in build-fuzz/corpus/)
# Each target starts from its working corpus (build-fuzz/corpus/NAME, kept between runs) plus seeds assembled from
# fuzz/seeds/NAME, tests/data (the malformed corpus, the OpenSubdiv shapes, the teapot: small files of the target's format).
# Crashes, leaks, timeouts (> 10 s per input) and out-of-memory (> 2 GiB) are saved as build-fuzz/artifacts/NAME-*;
# reproduce one with `build-fuzz/fuzz/NAME FILE`, then add it to tests/data/malformed (tests/io/malformed_test.cpp).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
shift || true
build=${FUZZ_BUILD_DIR:-build-fuzz}
export CCACHE_BASEDIR="$PWD" CCACHE_NOHASHDIR=1
start=$(date +%s)

missing=()
for p in clang-14 libfuzzer-14-dev llvm-14; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing: ${missing[*]}"
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

if [ ! -f "$build/build.ninja" ]; then
  CC=clang-14 CXX=clang++-14 cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSURFACED_FUZZ=ON \
    -DSURFACED_BUILD_TESTS=OFF -DSURFACED_BUILD_BENCH=OFF -DSURFACED_WERROR=OFF >/dev/null
else
  cmake "$build" >/dev/null  # picks up targets added since (e.g. fuzz_scene once api/scene_codec.h exists)
fi
read -r -a all_targets < <(tr ';' ' ' < "$build/fuzz_targets.txt")
targets=("$@"); [ ${#targets[@]} -gt 0 ] || targets=("${all_targets[@]}")
# the machine may be shared: at most as many compile jobs as cores, and never two builds at once (the lock dev-build.sh takes)
flock /tmp/surfaced-build.lock cmake --build "$build" -j"$(nproc)" --target "${targets[@]}"
echo "== fuzz build done in $(( $(date +%s) - start )) s"

# file extensions whose files seed each target
seed_patterns() {
  case "$1" in
    fuzz_obj|fuzz_repair) echo "*.obj" ;;
    fuzz_off) echo "*.off" ;;
    fuzz_ply) echo "*.ply" ;;
    fuzz_stl) echo "*.stl" ;;
    fuzz_bez) echo "*.bez *.bbp" ;;
    fuzz_glb) echo "*.glb" ;;
    fuzz_gltf_json) echo "*.gltf" ;;
    fuzz_glb_points) echo "*.glb *.gltf" ;;
    *) echo "" ;;
  esac
}

failed=()
for t in "${targets[@]}"; do
  corpus="$build/corpus/$t" seeds="$build/seeds/$t" artifacts="$build/artifacts"
  mkdir -p "$corpus" "$artifacts"
  rm -rf "$seeds"; mkdir -p "$seeds"
  [ -d "fuzz/seeds/$t" ] && cp fuzz/seeds/"$t"/* "$seeds"/ 2>/dev/null || true
  for pattern in $(seed_patterns "$t"); do
    for dir in tests/data; do
      [ -d "$dir" ] || continue
      find "$dir" -type f -name "$pattern" -size -16k -print0 |
        while IFS= read -r -d '' f; do cp "$f" "$seeds/$(echo "$f" | tr '/' '_')"; done
    done
  done
  dict=()
  [ -f "fuzz/dict/$t.dict" ] && dict=(-dict="fuzz/dict/$t.dict")
  t0=$(date +%s)
  log="$build/$t.log"
  # -timeout: one input may run 30 s. Instrumented (ASan + UBSan + coverage) code runs 10-20x slower than a release
  # build: a /curves arc length to its 1e-12 tolerance floor takes 0.7 s in release and about 12 s here.
  if "$build/fuzz/$t" -max_total_time="$seconds" -timeout=30 -rss_limit_mb=2048 -max_len=65536 \
       -artifact_prefix="$artifacts/$t-" -print_final_stats=1 "${dict[@]}" "$corpus" "$seeds" >"$log" 2>&1; then
    runs=$(awk '/stat::number_of_executed_units/{print $2}' "$log")
    cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1)
    echo "== $t: $runs runs in $(( $(date +%s) - t0 )) s, $cov, corpus $(ls "$corpus" | wc -l) files, no findings"
  else
    echo "== $t: FOUND A PROBLEM (log $log):" >&2
    grep -E 'ERROR|SUMMARY|fuzz invariant|Test unit written|deadly signal' "$log" | head -8 >&2
    failed+=("$t")
  fi
done
echo "== fuzzing done in $(( $(date +%s) - start )) s (${#targets[@]} targets, $seconds s each)"
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzz findings in: ${failed[*]} (artifacts in $build/artifacts/)" >&2
  exit 1
fi
