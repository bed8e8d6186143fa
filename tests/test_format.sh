#!/bin/sh
# The C sources follow the committed .clang-format. Skipped (77) when clang-format is missing.
# usage: test_format.sh SOURCE_DIR
cd "$1" || exit 1
command -v clang-format >/dev/null 2>&1 || { echo "clang-format not installed: skipped"; exit 77; }
files=$(find include src tools tests bench fuzz examples -name '*.[ch]' -o -name '*.cpp')
if clang-format --dry-run --Werror $files 2>"${TMPDIR:-/tmp}/mm_format.$$"; then
    echo "test_format: $(echo "$files" | wc -l) files follow .clang-format"
    rm -f "${TMPDIR:-/tmp}/mm_format.$$"
    exit 0
fi
head -20 "${TMPDIR:-/tmp}/mm_format.$$"
rm -f "${TMPDIR:-/tmp}/mm_format.$$"
echo "run: clang-format -i \$(git ls-files '*.c' '*.h' '*.cpp')"
exit 1
