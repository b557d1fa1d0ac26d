#!/usr/bin/env bash
# Installs the benchmark-only peers, builds the benchmarks and runs them: ours against the reference in one process
# each (OpenSubdiv for subdivision, meshoptimizer and CGAL for simplification, CGAL's AABB_tree and Embree 3 for
# spatial queries), plus implicit meshing, patch tessellation and mesh repair against the simplification it precedes.
# Debian 12, as root for the installs. The peers are never linked into the service.
#   scripts/bench.sh                       every benchmark, full size (the 1M-triangle simplifications take minutes)
#   scripts/bench.sh --quick               smaller meshes only
#   scripts/bench.sh simplify [--quick]    some of: subdivide simplify implicit tessellate repair spatial grid poisson
# Each output also goes to build/bench-results/NAME.md.
set -euo pipefail
cd "$(dirname "$0")/.."

quick=()
selected=()
for arg in "$@"; do
  case "$arg" in
    --quick) quick=(--quick) ;;
    subdivide|simplify|implicit|tessellate|repair|spatial|grid|poisson) selected+=("$arg") ;;
    *) echo "usage: scripts/bench.sh [--quick] [subdivide|simplify|implicit|tessellate|repair|spatial|grid|poisson]..." >&2; exit 2 ;;
  esac
done
[ ${#selected[@]} -gt 0 ] || selected=(subdivide simplify implicit tessellate repair spatial grid poisson)

# The build dependencies come from scripts/install-deps.sh (run it first on a fresh machine); here only the bench-only
# peers: meshoptimizer, CGAL (header-only; pulls Boost, GMP, MPFR) and Eigen (CGAL's Garland-Heckbert policies use
# it), Embree 3 (the spatial queries' ray peer), OpenVDB (the distance grid's peer; its CMake Find module needs
# Boost.Iostreams). The scanned bunny is tests/data/bunny.
command -v cmake >/dev/null && dpkg-query -W libosd-dev >/dev/null 2>&1 ||
  { echo "run scripts/install-deps.sh first (build dependencies)" >&2; exit 1; }
bench_packages=(libmeshoptimizer-dev libcgal-dev libeigen3-dev libembree-dev libopenvdb-dev libboost-iostreams-dev)
missing=()
for p in "${bench_packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing: ${missing[*]}"
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# A build tree configured before CGAL or Embree was installed does not know their targets yet: configure again (under
# the build lock that scripts/dev-build.sh takes, so as not to disturb a build in progress).
if [ -f build/build.ninja ] &&
  ! { grep -q bench_simplify_cgal build/build.ninja && grep -q bench_spatial_peers build/build.ninja &&
    grep -q bench_grid_openvdb build/build.ninja && grep -q bench_poisson_cgal build/build.ninja; }; then
  flock /tmp/surfaced-build.lock cmake -S . -B build >/dev/null
fi

targets=()
for name in "${selected[@]}"; do
  case "$name" in
    simplify) targets+=(bench_simplify_cgal) ;;
    spatial) targets+=(bench_spatial_peers) ;;
    grid) targets+=(bench_grid_openvdb) ;;
    poisson) targets+=(bench_poisson_cgal) ;;
    tessellate) [ -f bench/tessellate_bench.cpp ] && targets+=(bench_tessellate) ;;
    *) targets+=("bench_$name") ;;
  esac
done
scripts/dev-build.sh "${targets[@]}"

mkdir -p build/bench-results
for name in "${selected[@]}"; do
  binary=build/bench/bench_$name
  [ "$name" = simplify ] && binary=build/bench/bench_simplify_cgal
  [ "$name" = spatial ] && binary=build/bench/bench_spatial_peers
  [ "$name" = grid ] && binary=build/bench/bench_grid_openvdb
  [ "$name" = poisson ] && binary=build/bench/bench_poisson_cgal
  if [ ! -x "$binary" ]; then
    echo "== $name: $binary not built, skipped" >&2
    continue
  fi
  echo "== $name ($(date -u +%FT%TZ), $binary ${quick[*]})"
  args=("${quick[@]}")
  [ "$name" = repair ] && args=()  # one 1M-triangle mesh, no --quick
  "$binary" "${args[@]}" | tee "build/bench-results/$name.md"
done
