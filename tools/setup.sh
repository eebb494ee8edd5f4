#!/usr/bin/env bash
# Installs every Debian package pushpin needs to build, test and benchmark.
# Idempotent: when everything is present it only checks and returns in seconds.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git
  clang libclang-rt-14-dev
  libopenimageio-dev openimageio-tools libopenexr-dev libwebp-dev
  libembree-dev libzstd-dev libglm-dev libtbb-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libosd-dev
  gnome-backgrounds blender-data
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages present"
  exit 0
fi

echo "setup: installing ${missing[*]}"
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
