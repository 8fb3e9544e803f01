#!/bin/bash
# The code's style, as .clang-format and setup.cfg's [flake8] describe it: C++ through clang-format (no change
# wanted), Python through flake8.  Exits 1 and names the files that differ.
set -uo pipefail
cd "$(dirname "$0")/.."
status=0
mapfile -t cpp < <(git ls-files 'native/*.h' 'native/*.cpp' 'tests/native/*.h' 'tests/native/*.cpp')
log=$(mktemp)
trap 'rm -f "$log"' EXIT
if ! clang-format --dry-run --Werror "${cpp[@]}" 2> "$log"; then
  grep -o '^[^:]*' "$log" | sort -u | sed 's/^/clang-format would change: /'
  echo "fix: clang-format -i \$(git ls-files 'native/*.h' 'native/*.cpp' 'tests/native/*.h' 'tests/native/*.cpp')"
  status=1
fi
/usr/bin/python3 -m flake8 setup.py python addon tests scripts experiments || status=1
if ((status == 0)); then echo "style: clang-format and flake8 clean"; fi
exit $status
