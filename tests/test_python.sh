#!/bin/sh
# The Python package (python/): installed with pip into a temporary folder (its own copy of the
# libraries from the build tree: MM_LIBRARY_DIR), imported with only PYTHONPATH set (no
# LD_LIBRARY_PATH), its pytest suite run against a database of the built-in set. Skipped (exit 77)
# when no Python has numpy, pytest, pip and setuptools (Debian: python3-numpy python3-pytest
# python3-pip python3-setuptools).
# usage: test_python.sh MM_BINARY SOURCE_DIR BUILD_DIR OUT_DIR
set -u
mm=$1
src=$2
build=$3
out=$4
python=
# Debian's own interpreter first: the one its python3-* packages are for
for p in /usr/bin/python3 python3; do
    if "$p" -c "import setuptools, numpy, pytest, pip" >/dev/null 2>&1; then
        python=$p
        break
    fi
done
if [ -z "$python" ]; then
    echo "test_python: skipped: no python3 with numpy, pytest, pip and setuptools (apt-get install python3-numpy python3-pytest python3-pip python3-setuptools)"
    exit 77
fi
rm -rf "$out"
mkdir -p "$out"
fail() {
    echo "FAIL: $*"
    exit 1
}
"$mm" synth "$out/set" >/dev/null || fail "mm synth"
"$mm" db build "$src/configs/synth.json" --data "$out/set" -o "$out/synth.mmdb" >/dev/null || fail "mm db build"
# pip builds in the folder it is given: a copy, so that the source tree stays clean
cp -r "$src/python" "$out/package"
rm -rf "$out/package/build" "$out/package"/*.egg-info
MM_SOURCE_DIR=$src MM_LIBRARY_DIR=$build PIP_DISABLE_PIP_VERSION_CHECK=1 \
    "$python" -m pip install --quiet --no-build-isolation --no-deps --no-index --target "$out/site" "$out/package" \
    >"$out/pip.log" 2>&1 || {
    cat "$out/pip.log"
    fail "pip install"
}
cd "$out" || fail "cd $out"
env -u LD_LIBRARY_PATH PYTHONPATH="$out/site" MM_TEST_DB="$out/synth.mmdb" MM_TEST_DATA="$out/set" MM_CLI="$mm" \
    MM_SOURCE_DIR="$src" "$python" -m pytest -q -p no:cacheprovider "$src/python/tests"
