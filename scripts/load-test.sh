#!/usr/bin/env bash
# Load and fault test of `surfaced serve` on loopback. Not part of CI: it saturates the machine.
# Usage: scripts/load-test.sh [BINARY]   (default build/server/surfaced; DURATION=60 CONNECTIONS=64 override)
#
#  1. mixed workload at saturation with wrk for DURATION s (livez, subdivide, simplify, teapot tessellation):
#     counts by status from the server's own /metrics (no 5xx other than 503 shedding allowed), p50/p99 from wrk,
#     RSS after a warm-up and after the run;
#  2. slowloris: 2 x threads connections that send half a request head and stop; /livez must still answer;
#  3. slow bodies: 2 x threads connections that send a head and half the body, then stop; /livez must still
#     answer, and each of them gets 408 once the body timeout (--body-timeout 5 here) passes;
#  4. SIGTERM under load: the server must exit 0, and every connection the kernel completed must be answered:
#     wrk must see no read errors (connect errors once the listener has closed are expected: those clients never
#     sent their request).
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=${1:-build/server/surfaced}
DURATION=${DURATION:-60}
CONNECTIONS=${CONNECTIONS:-64}
THREADS=$(nproc)
PORT=$((20000 + RANDOM % 20000))
URL=http://127.0.0.1:$PORT
work=$(mktemp -d)
trap 'kill "$pid" 2>/dev/null || true; rm -rf "$work"' EXIT
command -v wrk >/dev/null || { echo "wrk is not installed (apt-get install wrk)"; exit 2; }

cat >"$work/mixed.lua" <<'EOF'
local cube = "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n" ..
             "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n"
local requests = {}
local n = 0
init = function(args)
  requests[1] = wrk.format("GET", "/livez")
  requests[2] = wrk.format("POST", "/subdivide?levels=4&format=obj", {["Content-Type"] = "model/obj"}, cube)
  requests[3] = wrk.format("POST", "/subdivide?levels=3", {["Content-Type"] = "model/obj"}, cube)
  requests[4] = wrk.format("GET", "/patches/teapot?segments=6&format=obj")
  requests[5] = wrk.format("POST", "/simplify?ratio=0.5&format=obj", {["Content-Type"] = "model/obj"}, cube)
end
request = function()
  n = n + 1
  return requests[(n % #requests) + 1]
end
EOF

start_server() {
  "$BIN" serve --port "$PORT" --threads "$THREADS" --access-log off --deadline-ms 10000 \
    --body-timeout 5 >"$work/serve.out" 2>&1 &
  pid=$!
  for _ in $(seq 100); do "$BIN" healthcheck --port "$PORT" --timeout 1 >/dev/null 2>&1 && return; sleep 0.1; done
  echo "server did not start"; cat "$work/serve.out"; exit 1
}
rss_kib() { awk '/VmRSS/ {print $2}' "/proc/$pid/status"; }
status_counts() {
  curl -s "$URL/metrics" | awk '/^surfaced_http_requests_total/ {match($0, /status="[0-9]+"/);
    n[substr($0, RSTART + 8, RLENGTH - 9)] += $NF} END {for (s in n) printf "%s=%d ", s, n[s]; print ""}'
}

start_server
echo "== warm-up (10 s)"
wrk -t2 -c"$CONNECTIONS" -d10s -s "$work/mixed.lua" "$URL" >/dev/null
rss_before=$(rss_kib)
echo "== mixed workload: $CONNECTIONS connections, $DURATION s, $THREADS workers"
wrk -t2 -c"$CONNECTIONS" -d"${DURATION}s" --latency -s "$work/mixed.lua" "$URL" | tee "$work/wrk.txt"
rss_after=$(rss_kib)
counts=$(status_counts)
echo "statuses (server /metrics, warm-up included): $counts"
echo "RSS after warm-up: ${rss_before} KiB, after the run: ${rss_after} KiB"
bad=$(echo "$counts" | tr ' ' '\n' | awk -F= '$1 >= 500 && $1 != 503 {s += $2} END {print s + 0}')
echo "5xx other than 503: $bad"
curl -s "$URL/metrics" | grep -E '^surfaced_http_shed_total'

echo "== slowloris: $((2 * THREADS)) half-sent request heads"
for i in $(seq $((2 * THREADS))); do
  exec {fd}<>"/dev/tcp/127.0.0.1/$PORT"
  printf 'GET /livez HTTP/1.1\r\nHost: x\r\n' >&"$fd"
  eval "slow_$i=$fd"
done
if curl -s -m 15 -o /dev/null -w '%{http_code}' "$URL/livez" | grep -q 200; then
  echo "another client is still served while they hang: ok"
else
  echo "FAILED: /livez did not answer while slow clients held connections"; bad=$((bad + 1))
fi
for i in $(seq $((2 * THREADS))); do eval "exec {slow_$i}>&-"; done

echo "== slow bodies: $((2 * THREADS)) heads with half a body"
cube_obj=$'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n'
for i in $(seq $((2 * THREADS))); do
  exec {fd}<>"/dev/tcp/127.0.0.1/$PORT"
  printf 'POST /subdivide?format=obj HTTP/1.1\r\nHost: x\r\nContent-Type: model/obj\r\nContent-Length: %d\r\n\r\n%s' \
    "${#cube_obj}" "${cube_obj:0:10}" >&"$fd"
  eval "body_$i=$fd"
done
if curl -s -m 20 -o /dev/null -w '%{http_code}' "$URL/livez" | grep -q 200; then
  echo "another client is served while they trickle: ok"
else
  echo "FAILED: /livez did not answer while slow bodies held connections"; bad=$((bad + 1))
fi
timeouts=0
for i in $(seq $((2 * THREADS))); do
  eval "fd=\$body_$i"
  if timeout 20 head -c 12 <&"$fd" | grep -q '^HTTP/1.1 408'; then timeouts=$((timeouts + 1)); fi
  exec {fd}>&-
done
echo "slow bodies answered 408: $timeouts of $((2 * THREADS))"
[ "$timeouts" = $((2 * THREADS)) ] || bad=$((bad + 1))

echo "== SIGTERM under load"
wrk -t2 -c"$CONNECTIONS" -d10s -s "$work/mixed.lua" "$URL" >"$work/wrk-term.txt" 2>&1 &
wrk_pid=$!
sleep 4
kill -TERM "$pid"
set +e
wait "$pid"; code=$?
set -e
wait "$wrk_pid" || true
grep -E "requests in|Socket errors|Non-2xx" "$work/wrk-term.txt" || true
echo "server exit code: $code"
if [ "$code" != 0 ]; then bad=$((bad + 1)); fi
# A read error would be a connection the kernel completed but the server reset without answering (before the
# drain accepted the listen backlog, 9-39 of them per run).
read_errors=$(grep -oE "read [0-9]+" "$work/wrk-term.txt" | awk '{print $2}' || true)
echo "wrk read errors while stopping: ${read_errors:-0}"
if [ "${read_errors:-0}" != 0 ]; then bad=$((bad + 1)); fi
[ "$bad" = 0 ] && echo "load test: ok" || { echo "load test: FAILED"; exit 1; }
