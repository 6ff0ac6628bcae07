#!/usr/bin/env bash
# Installs the Debian 12 packages penumbra needs, only those that are missing.
# Run as root (or with sudo available). Every dependency is a Debian package by name.
set -euo pipefail

packages=(
    cmake g++ make pkg-config git
    libopenmesh-dev libglm-dev libtinygltf-dev libembree-dev nlohmann-json3-dev libcli11-dev
    libstb-dev libglfw3-dev libepoxy-dev libegl-dev libgl-dev libimgui-dev
    xvfb xauth libglx-mesa0               # a display for the viewer tests and scripted captures
    libgtest-dev libbenchmark-dev
    libegl-mesa0 libgl1-mesa-dri          # EGL + llvmpipe: the headless renderer and GL tests
    python3 python3-matplotlib python3-numpy
    clang-14 libclang-rt-14-dev           # libFuzzer + sanitizers: scripts/fuzz.sh
)

missing=()
for p in "${packages[@]}"; do
    status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
    [[ "$status" == "install ok installed" ]] || missing+=("$p")
done

if ((${#missing[@]} == 0)); then
    echo "install-deps: all ${#packages[@]} packages present"
    exit 0
fi

echo "install-deps: installing ${missing[*]}"
sudo=()
if [[ $(id -u) -ne 0 ]]; then
    command -v sudo >/dev/null || { echo "install-deps: not root and no sudo" >&2; exit 1; }
    sudo=(sudo)
fi
export DEBIAN_FRONTEND=noninteractive
"${sudo[@]}" apt-get update -qq
"${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
