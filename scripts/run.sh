#!/usr/bin/env bash
# Installs what is needed, builds, and runs the service with its web client on http://127.0.0.1:8080 .
set -euo pipefail
cd "$(dirname "$0")/.."
SURFACED_SKIP_NPM=1 scripts/install-deps.sh
scripts/build.sh surfaced
exec build/server/surfaced serve --host "${HOST:-127.0.0.1}" --port "${PORT:-8080}" --web-root clients/web
