#!/bin/sh
# Installs the Debian packages mm needs (with sudo when not root) and builds it into build/.
# usage: scripts/setup.sh [--program-only] [extra cmake arguments]
#   --program-only: build the mm program alone (not the tests and benchmarks): the demo's path
set -e
cd "$(dirname "$0")/.."
target=""
if [ "${1:-}" = "--program-only" ]; then
    target="--target mm_cli"
    shift
fi
# OSMesa: headless rendering; GLFW: the viewer's window; Dear ImGui: its panel (DejaVu: its font);
# ffmpeg: MP4 and GIF output.
packages="build-essential cmake pkg-config libcmocka-dev libcjson-dev libassimp-dev zlib1g-dev libosmesa6-dev libglfw3-dev libimgui-dev fonts-dejavu-core ffmpeg"
missing=""
for p in $packages; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
if [ -n "$missing" ]; then
    sudo=""
    [ "$(id -u)" -eq 0 ] || sudo=sudo
    echo "setup: installing$missing"
    $sudo apt-get update -qq
    $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $missing >/dev/null
fi
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
# shellcheck disable=SC2086
cmake --build build -j"$(nproc)" $target
