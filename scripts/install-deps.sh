#!/usr/bin/env bash
# Installs everything surfaced needs to build, run and test, on Debian 12 as root. Idempotent.
#   scripts/install-deps.sh            build + run + test dependencies
#   SURFACED_SKIP_NPM=1 ...            skip the npm packages used by tests
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(
  build-essential cmake ninja-build ccache pkg-config git
  clang-format          # tests: scripts/check-format.sh (the code follows .clang-format)
  libosd-dev            # OpenSubdiv: the reference in tests and benchmarks (never linked into the service)
  libocct-modeling-data-dev libocct-foundation-dev  # OpenCASCADE: the NURBS reference in tests (never linked into the service)
  libtbb-dev            # OpenCASCADE's CMake targets link /usr/lib/x86_64-linux-gnu/libtbb.so, which only this package has
  libcpp-httplib-dev    # HTTP server
  nlohmann-json3-dev    # JSON
  libdraco-dev draco    # Draco compression (library + CLI tools)
  libtinygltf-dev       # glTF writer/reader (compiled into our own TU)
  libeigen3-dev         # needed by Draco's headers
  libgtest-dev libgmock-dev
  libmeshoptimizer-dev  # benchmarks only: meshoptimizer as the simplification peer (never linked into the service)
  python3-yaml          # tests: deploy/ (Kubernetes manifests) parsed by tests/deploy/manifests_test.py
  python3-venv python3-pip python3-setuptools python3-wheel  # tests: pip install of clients/python into a venv
  chromium              # tests: the web client's browser tests (Playwright drives /usr/bin/chromium headless)
  ca-certificates
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing: ${missing[*]}"
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# Node.js, for the tests' tools (the Khronos glTF validator, the OpenAPI validator, Playwright for the browser test).
# A machine that has its own Node (20 and npm 10+ here) keeps it; a bare Debian 12 gets Debian's nodejs and npm.
# The web client needs none of it: its three.js is vendored in clients/web/vendor (scripts/vendor-web.sh updates it).
if [ "${SURFACED_SKIP_NPM:-0}" != 1 ] && [ -f tests/package.json ]; then
  if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
    echo "installing: nodejs npm (Debian's)"
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends nodejs npm
  fi
  if [ ! -d tests/node_modules ] || [ tests/package-lock.json -nt tests/node_modules/.package-lock.json ]; then
    npm ci --prefix tests --no-audit --no-fund --loglevel=error
  fi
fi
