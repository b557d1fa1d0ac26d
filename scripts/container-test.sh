#!/usr/bin/env bash
# Builds the container image from this checkout as a user would (`podman build --format docker -t IMAGE .`: the
# Dockerfile compiles the service only; its compiler cache lives in a cache mount, so a rebuild recompiles what
# changed), from a locally debootstrapped Debian 12 base, runs it on loopback, and checks it as an operator would:
#   health (podman healthcheck run -> `surfaced healthcheck` inside), the web client is served, POST /subdivide -> a
#   GLB the Khronos validator accepts, the server process is not root, SIGTERM -> exit status 0 within a few seconds.
# The container is removed whatever happens. Run as root (podman rootful). Idempotent.
#   SURFACED_IMAGE=localhost/surfaced:test   image tag
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
image=${SURFACED_IMAGE:-localhost/surfaced:test}
name=surfaced-ct-$$
work=$(mktemp -d)

cleanup() {
  podman rm -f -t 3 "$name" >/dev/null 2>&1 || true
  rm -rf "$work"
}
trap cleanup EXIT INT TERM
fail() { echo "container test FAILED: $*" >&2; podman logs --tail 30 "$name" >&2 2>/dev/null || true; exit 1; }

scripts/container-setup.sh

# ---- build: as a user builds it (podman's --format docker keeps the HEALTHCHECK, which the OCI format has no field
# for; docker build keeps it without a flag)
t0=$(date +%s)
# niced: on a shared development machine the interactive builds go first
nice -n 10 podman build --format docker --pull=never --layers -t "$image" . >"$work/build.log" 2>&1 ||
  { tail -60 "$work/build.log" >&2; fail "image build (log above)"; }
grep -E '^(runtime packages|[[:space:]]*(Hits|Misses))' "$work/build.log" | sed 's/^/   /' || true
podman image prune -f >/dev/null 2>&1 || true  # earlier builds' layers, untagged now (GBs per build otherwise)
echo "== container image built in $(( $(date +%s) - t0 )) s ($(podman image inspect -f '{{.Size}}' "$image" |
  awk '{printf "%.0f MB", $1/1e6}'))"

# ---- image metadata: non-root user, health check, port
[ "$(podman image inspect -f '{{.Config.User}}' "$image")" != "" ] || fail "image has no USER"
case "$(podman image inspect -f '{{.Config.User}}' "$image")" in 0|0:*|root|root:*) fail "image USER is root";; esac
podman image inspect -f '{{.Config.Healthcheck.Test}}' "$image" | grep 'surfaced healthcheck' >/dev/null ||
  fail "image has no HEALTHCHECK (built without --format docker?)"
podman image inspect -f '{{json .Config.ExposedPorts}}' "$image" | grep '"8080/tcp"' >/dev/null || fail "image does not expose 8080"

# ---- run on a free loopback port
port=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
# (without systemd podman cannot schedule the periodic checks and says so on stderr; `healthcheck run` still works)
podman run -d --name "$name" -p 127.0.0.1:"$port":8080 "$image" >/dev/null 2>"$work/run.err" ||
  { cat "$work/run.err" >&2; fail "podman run"; }
healthy=0
for _ in $(seq 1 60); do
  if podman healthcheck run "$name" >/dev/null 2>&1; then healthy=1; break; fi
  [ "$(podman inspect -f '{{.State.Running}}' "$name")" = true ] || fail "container exited while starting"
  sleep 0.5
done
[ $healthy = 1 ] || fail "not healthy after 30 s"
echo "   healthy: $(podman inspect -f '{{.State.Health.Status}}' "$name") after $(( $(date +%s) - t0 )) s since build start"
curl -fsS "http://127.0.0.1:$port/livez" >/dev/null || fail "GET /livez from the host"
# the web client and its vendored three.js are in the image
# (to a file, then grep: `curl | grep -q` under pipefail fails when grep exits before curl has written everything)
curl -fsS -o "$work/index.html" "http://127.0.0.1:$port/" || fail "GET / from the host"
grep -qi '<html' "$work/index.html" || fail "GET / does not serve the web client"
curl -fsS -o /dev/null "http://127.0.0.1:$port/vendor/three/three.module.js" || fail "the web client's three.js is not served"

# ---- a real request: a cube, Catmull-Clark level 2, Draco GLB back; the Khronos validator must report no errors
curl -sS -o "$work/out.glb" -w '%{http_code} %{content_type}\n' -X POST "http://127.0.0.1:$port/subdivide" \
  -H 'Content-Type: application/json' -d '{"mesh":{"positions":[[0,0,0],[1,0,0],[1,1,0],[0,1,0],[0,0,1],[1,0,1],[1,1,1],[0,1,1]],"faces":[[0,3,2,1],[4,5,6,7],[0,1,5,4],[1,2,6,5],[2,3,7,6],[3,0,4,7]]},"scheme":"catmull-clark","levels":2}' \
  >"$work/status" || fail "POST /subdivide"
read -r code ctype <"$work/status"
[ "$code" = 200 ] || fail "POST /subdivide answered $code: $(head -c 400 "$work/out.glb")"
[ "$ctype" = model/gltf-binary ] || fail "POST /subdivide content type $ctype"
node tests/tools/validate_gltf.mjs "$work/out.glb" >"$work/report" || fail "the glTF validator did not run"
read -r errors warnings _ <"$work/report"
[ "$errors" = 0 ] && [ "$warnings" = 0 ] || { head -c 2000 "$work/report" >&2; fail "validator: $errors errors, $warnings warnings"; }
grep -q '"KHR_draco_mesh_compression"' "$work/report" || fail "the GLB is not Draco-compressed"
echo "   POST /subdivide: $(stat -c %s "$work/out.glb") bytes of GLB, validator: 0 errors, 0 warnings"

# ---- the service process is not root (on the host, without user namespaces, its uid is the image's user)
pid=$(podman inspect -f '{{.State.Pid}}' "$name")
uid=$(awk '/^Uid:/{print $2}' "/proc/$pid/status")
[ -n "$uid" ] && [ "$uid" != 0 ] || fail "the service runs as uid '$uid'"
comm=$(cat "/proc/$pid/comm")
[ "$comm" = surfaced ] || fail "PID 1 of the container is '$comm', not surfaced"
echo "   process: $comm, pid 1 in the container, uid $uid ($(podman top "$name" user | tail -1 | tr -d ' '))"

# ---- SIGTERM: exits by itself (no --init, no SIGKILL from podman: stop timeout 30 s) with status 0, promptly
t1=$(date +%s.%N)
podman kill -s TERM "$name" >/dev/null || fail "podman kill -s TERM"
status=$(timeout 20 podman wait "$name") || fail "still running 20 s after SIGTERM"
elapsed=$(python3 -c "import time; print(round(time.time() - $t1, 2))")
[ "$status" = 0 ] || fail "exit status $status after SIGTERM"
awk -v e="$elapsed" 'BEGIN{exit !(e < 10)}' || fail "took $elapsed s to exit after SIGTERM"
printf '   SIGTERM: exit status 0 after %.2f s\n' "$elapsed"
echo "== container test done in $(( $(date +%s) - start )) s"
