#!/usr/bin/env bash
# Updates the vendored copy of three.js in clients/web/vendor/ (committed; served by `surfaced serve`, so the client
# works offline, with no CDN and no npm at build or run time) from npm, at the version clients/web/package.json pins.
# Run it after changing that pin, and commit the result. clients/web/node_modules/ is not in git.
set -euo pipefail
cd "$(dirname "$0")/../clients/web"
if [ ! -f node_modules/three/package.json ] || [ package-lock.json -nt node_modules/.package-lock.json ]; then
  npm ci --no-audit --no-fund --loglevel=error
fi
src=node_modules/three
want=$(node -p "require('./package.json').dependencies.three")
have=$(node -p "require('./$src/package.json').version")
[ "$want" = "$have" ] || { echo "vendor-web: three $have installed, package.json pins $want" >&2; exit 1; }
rm -rf vendor.tmp
mkdir -p vendor.tmp/three/addons/controls vendor.tmp/three/addons/loaders vendor.tmp/three/addons/utils vendor.tmp/draco
cp "$src/build/three.module.js" "$src/build/three.core.js" vendor.tmp/three/
cp "$src/examples/jsm/controls/OrbitControls.js" vendor.tmp/three/addons/controls/
cp "$src/examples/jsm/loaders/GLTFLoader.js" "$src/examples/jsm/loaders/DRACOLoader.js" vendor.tmp/three/addons/loaders/
cp "$src/examples/jsm/utils/BufferGeometryUtils.js" "$src/examples/jsm/utils/SkeletonUtils.js" vendor.tmp/three/addons/utils/
# the full Draco decoder, not libs/draco/gltf/ (meshes only): the point cloud view reads Draco POINTS GLBs
cp "$src"/examples/jsm/libs/draco/draco_decoder.js "$src"/examples/jsm/libs/draco/draco_decoder.wasm \
   "$src"/examples/jsm/libs/draco/draco_wasm_wrapper.js vendor.tmp/draco/
cp "$src/LICENSE" vendor.tmp/three/LICENSE
echo "$have" > vendor.tmp/three/VERSION
rm -rf vendor && mv vendor.tmp vendor
echo "vendor-web: three $have -> clients/web/vendor/"
