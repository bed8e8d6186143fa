#!/bin/sh
# Installs the Debian packages mm needs (with sudo when not root) and builds it into build/.
# usage: scripts/setup.sh [extra cmake arguments]
set -e
cd "$(dirname "$0")/.."
packages="build-essential cmake pkg-config libcmocka-dev libcjson-dev libassimp-dev"
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
cmake --build build -j"$(nproc)"
