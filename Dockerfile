# syntax=docker/dockerfile:1.4
# surfaced: build and test in one stage, run from a small Debian 12 stage with only the runtime libraries.
#
#   podman build --format docker --build-context shared=../shared -v "$(ccache -k cache_dir)":/ccache \
#     --build-arg SRC_DIR="$PWD" --build-arg SHARED_DIR="$(dirname "$PWD")/shared" -t localhost/surfaced:test .
#   (scripts/container-test.sh does this, and runs the image)
#
# --build-context shared=../shared: the reference data the test suite reads (OpenSubdiv's regression shapes, the
# teapot); docker buildx takes the same flag. --format docker keeps the HEALTHCHECK (OCI images drop it).
# -v HOST_CCACHE:/ccache (optional; podman/buildah only) shares the host's compiler cache with the build stage, so a
# rebuild after a source change only recompiles what changed. Without it the build is cold every time.
# Base: debian:bookworm; on a machine without a registry, scripts/container-setup.sh makes it with debootstrap.

FROM debian:bookworm AS deps
ENV DEBIAN_FRONTEND=noninteractive LANG=C.UTF-8
# 1. build + test dependencies: scripts/install-deps.sh's packages (tests/deploy/manifests_test.py keeps the two
#    lists in step) without the benchmark peer and the browser (the Chromium test runs on the host, not in here),
#    plus Debian's Node for the Khronos glTF / OpenAPI validator tests (pure JavaScript, copied in with
#    tests/node_modules). Nothing from the source tree is copied before this layer, so source edits keep it cached.
RUN apt-get update -qq \
 && apt-get install -y -qq --no-install-recommends \
      build-essential cmake ninja-build ccache pkg-config git \
      libosd-dev libcpp-httplib-dev nlohmann-json3-dev libdraco-dev draco libtinygltf-dev libeigen3-dev \
      libgtest-dev libgmock-dev glmark2-data python3-yaml ca-certificates \
      nodejs \
 && rm -rf /var/lib/apt/lists/*

FROM deps AS build
# Sources at the same absolute path as the host's checkout (SRC_DIR, passed by scripts/container-test.sh): the tests
# compile absolute paths into their objects (source and data directories), so only then does the host's compiler
# cache serve them. The shared reference data sits beside the sources, where the tests look for it (../shared).
ARG SRC_DIR=/src/main
ARG SHARED_DIR=/src/shared
COPY --from=shared data ${SHARED_DIR}/data
# 2. sources, build, the whole test suite (a failing test fails the image build), except the web client's Chromium
#    test (label browser: it needs a browser this stage does not install; CI runs it on the host)
COPY . ${SRC_DIR}
WORKDIR ${SRC_DIR}
ENV CCACHE_DIR=/ccache CCACHE_BASEDIR=${SRC_DIR} CCACHE_NOHASHDIR=1
RUN mkdir -p /ccache && { mountpoint -q /ccache || export CCACHE_DISABLE=1; } \
 && cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSURFACED_WERROR=ON -DSURFACED_BUILD_BENCH=OFF >/dev/null \
 && cmake --build build -j"$(nproc)" \
 && (cd build && ctest --output-on-failure -j"$(nproc)" --timeout 600 -LE browser) \
 && (cd build && ctest -N | tail -1)
# 3. what the runtime stage takes: the stripped binary, and the Debian packages of the shared libraries it loads
RUN mkdir -p /out && strip -o /out/surfaced build/server/surfaced && cp -r clients/web /out/web \
 && for lib in $(ldd /out/surfaced | awk '/=> \//{print $3}'); do \
      dpkg -S "$lib" 2>/dev/null || dpkg -S "$(readlink -f "$lib")"; \
    done | cut -d: -f1 | sort -u > /out/runtime-packages.txt \
 && echo "runtime packages: $(tr '\n' ' ' < /out/runtime-packages.txt)"

FROM debian:bookworm
ENV LANG=C.UTF-8
COPY --from=build /out/runtime-packages.txt /tmp/runtime-packages.txt
RUN apt-get update -qq \
 && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $(cat /tmp/runtime-packages.txt) \
 && rm -rf /var/lib/apt/lists/* /var/cache/apt/archives/*.deb /tmp/runtime-packages.txt \
 && useradd --system --uid 10001 --user-group --no-create-home --home-dir /nonexistent --shell /usr/sbin/nologin surfaced
COPY --from=build /out/surfaced /usr/bin/surfaced
COPY --from=build /out/web /usr/share/surfaced/web
USER 10001:10001
EXPOSE 8080
HEALTHCHECK --interval=15s --timeout=3s --start-period=5s --retries=3 CMD ["surfaced", "healthcheck"]
# exec form: surfaced is PID 1 and gets SIGTERM itself (it finishes in-flight requests, then exits 0)
ENTRYPOINT ["surfaced", "serve", "--host", "0.0.0.0", "--port", "8080", "--web-root", "/usr/share/surfaced/web"]
