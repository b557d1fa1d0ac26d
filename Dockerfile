# syntax=docker/dockerfile:1.4
# surfaced: the service and its web client in a small Debian 12 image, running as a non-root user.
#
#   docker build -t surfaced .            (or: podman build --format docker -t surfaced .)
#   docker run --rm -p 8080:8080 surfaced
#
# Stages: `build` compiles the service only (no tests, no benchmarks); the last stage is the runtime image, with the
# web client (its three.js is vendored in the repository: the build reaches nothing but Debian's archive).
# `docker build --target test .` builds and runs the test suite instead (CI runs it on the host, through
# scripts/test.sh). The compiler cache lives in a cache mount, so a rebuild after a source change recompiles only what
# changed. podman: `--format docker` keeps the HEALTHCHECK (the OCI image format has no field for it).

FROM debian:bookworm AS deps
ENV DEBIAN_FRONTEND=noninteractive LANG=C.UTF-8
# what the service needs to build; nothing from the source tree is copied before this layer, so edits keep it cached
RUN apt-get update -qq \
 && apt-get install -y -qq --no-install-recommends \
      build-essential cmake ninja-build ccache pkg-config ca-certificates \
      libcpp-httplib-dev nlohmann-json3-dev libdraco-dev libtinygltf-dev libeigen3-dev \
 && rm -rf /var/lib/apt/lists/*

FROM deps AS build
COPY . /src
WORKDIR /src
ENV CCACHE_DIR=/ccache CCACHE_BASEDIR=/src CCACHE_NOHASHDIR=1
RUN --mount=type=cache,target=/ccache \
    cmake -S . -B /build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSURFACED_WERROR=ON \
      -DSURFACED_BUILD_TESTS=OFF -DSURFACED_BUILD_BENCH=OFF >/dev/null \
 && cmake --build /build -j"$(nproc)" --target surfaced \
 && ccache -s | grep -E 'Hits|Misses' || true
# the stripped binary, and the Debian packages of the shared libraries it loads (installed in the runtime stage)
RUN mkdir -p /out && strip -o /out/surfaced /build/server/surfaced \
 && for lib in $(ldd /out/surfaced | awk '/=> \//{print $3}'); do \
      dpkg -S "$lib" 2>/dev/null || dpkg -S "$(readlink -f "$lib")"; \
    done | cut -d: -f1 | sort -u > /out/runtime-packages.txt \
 && echo "runtime packages: $(tr '\n' ' ' < /out/runtime-packages.txt)"

# optional: the whole test suite (not part of the default build; `docker build --target test .`)
FROM deps AS test
RUN apt-get update -qq \
 && apt-get install -y -qq --no-install-recommends git libosd-dev libocct-modeling-data-dev libocct-foundation-dev libtbb-dev libgtest-dev libgmock-dev draco \
      python3-yaml python3-venv python3-pip python3-setuptools python3-wheel nodejs npm \
 && rm -rf /var/lib/apt/lists/*
COPY . /src
WORKDIR /src
ENV CCACHE_DIR=/ccache CCACHE_BASEDIR=/src CCACHE_NOHASHDIR=1
RUN --mount=type=cache,target=/ccache --mount=type=cache,target=/root/.npm \
    npm ci --prefix tests --no-audit --no-fund --loglevel=error \
 && cmake -S . -B /build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSURFACED_WERROR=ON \
      -DSURFACED_BUILD_BENCH=OFF >/dev/null \
 && cmake --build /build -j"$(nproc)" \
 && cd /build && ctest --output-on-failure -j"$(nproc)" --timeout 600 -LE browser

FROM debian:bookworm AS runtime
ENV LANG=C.UTF-8
COPY --from=build /out/runtime-packages.txt /tmp/runtime-packages.txt
RUN apt-get update -qq \
 && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $(cat /tmp/runtime-packages.txt) \
 && rm -rf /var/lib/apt/lists/* /var/cache/apt/archives/*.deb /tmp/runtime-packages.txt \
 && useradd --system --uid 10001 --user-group --no-create-home --home-dir /nonexistent --shell /usr/sbin/nologin surfaced
COPY --from=build /out/surfaced /usr/bin/surfaced
COPY clients/web/index.html clients/web/style.css clients/web/favicon.svg /usr/share/surfaced/web/
COPY clients/web/js /usr/share/surfaced/web/js
COPY clients/web/vendor /usr/share/surfaced/web/vendor
COPY LICENSE THIRD_PARTY_NOTICES.md /usr/share/doc/surfaced/
USER 10001:10001
EXPOSE 8080
HEALTHCHECK --interval=15s --timeout=3s --start-period=5s --retries=3 CMD ["surfaced", "healthcheck"]
# exec form: surfaced is PID 1 and gets SIGTERM itself (it finishes in-flight requests, then exits 0)
ENTRYPOINT ["surfaced", "serve", "--host", "0.0.0.0", "--port", "8080", "--web-root", "/usr/share/surfaced/web"]
