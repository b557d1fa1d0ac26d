#!/usr/bin/env bash
# One-time, idempotent setup for building and running the container image without a Docker engine or a registry
# (the machines this project runs on have no Docker engine and reach no container registry, only Debian's archive):
# podman + buildah + runc, a containers.conf that works here (runc, explicit ulimits), and a debian:bookworm base image made locally by debootstrap from the same archive apt uses on this machine.
# The debootstrapped root is cached outside the repository (SURFACED_CONTAINER_CACHE, default
# /var/cache/surfaced-container) so a fresh clone does not redo it; the image is re-imported from it when podman's
# storage has lost it. Run as root.
set -euo pipefail

cache=${SURFACED_CONTAINER_CACHE:-/var/cache/surfaced-container}
base_tag=localhost/debian:bookworm

packages=(podman buildah runc debootstrap uidmap ca-certificates curl python3)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing: ${missing[*]}"
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# crun fails on this kind of host (cgroups hybrid mode), and podman run fails on rlimits without default_ulimits.
conf=/etc/containers/containers.conf
if ! grep -qs 'surfaced: container-setup v3' "$conf"; then
  mkdir -p /etc/containers
  [ -f "$conf" ] && ! grep -qs 'surfaced: container-setup' "$conf" && cp "$conf" "$conf.before-surfaced"
  cat > "$conf" <<'CONF'
# surfaced: container-setup v3 (runc: crun fails under cgroups hybrid mode; explicit ulimits or podman run fails)
[containers]
default_ulimits = ["nofile=20000:20000", "nproc=4096:4096"]
[engine]
runtime = "runc"
CONF
fi

if ! podman image exists "$base_tag"; then
  mkdir -p "$cache"
  tarball="$cache/debian-bookworm-minbase.tar"
  if [ ! -s "$tarball" ]; then
    # the archive apt already uses here (a mirror or snapshot the machine can reach)
    mirror=$(awk '/^URIs:/{print $2; exit}' /etc/apt/sources.list.d/debian.sources 2>/dev/null || true)
    mirror=${mirror:-http://deb.debian.org/debian}
    rootfs="$cache/rootfs.tmp"
    rm -rf "$rootfs"
    echo "debootstrap bookworm from $mirror (one-time, a few minutes)"
    debootstrap --variant=minbase bookworm "$rootfs" "$mirror" >"$cache/debootstrap.log" 2>&1 ||
      { tail -20 "$cache/debootstrap.log" >&2; exit 1; }
    rm -f "$rootfs/etc/apt/sources.list"
    if [ -f /etc/apt/sources.list.d/debian.sources ]; then
      mkdir -p "$rootfs/etc/apt/sources.list.d"
      cp /etc/apt/sources.list.d/debian.sources "$rootfs/etc/apt/sources.list.d/"
    else
      echo "deb $mirror bookworm main" > "$rootfs/etc/apt/sources.list"
    fi
    rm -rf "$rootfs"/var/cache/apt/archives/*.deb "$rootfs"/var/lib/apt/lists/*
    tar -C "$rootfs" -cf "$tarball.tmp" . && mv "$tarball.tmp" "$tarball"
    rm -rf "$rootfs"
  fi
  podman import "$tarball" "$base_tag" >/dev/null
fi
# FROM resolves only local tags; the Dockerfile says debian:bookworm
podman image exists docker.io/library/debian:bookworm || podman tag "$base_tag" docker.io/library/debian:bookworm
echo "container setup ok: $(podman --version), base $(podman image inspect -f '{{.Id}}' "$base_tag" | cut -c1-12)"
