#!/usr/bin/env bash
# Installs what is needed, builds, and runs every test. Exit status 0 only when all pass.
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
scripts/install-deps.sh
scripts/build.sh
echo "== build done in $(( $(date +%s) - start )) s"
cd build
ctest --output-on-failure -j"$(nproc)" --timeout 600
echo "== all tests done in $(( $(date +%s) - start )) s"
