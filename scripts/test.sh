#!/bin/bash
# All tests: C++ (ctest/GoogleTest), Python (pytest on the module), Blender (pytest inside headless Blender), style.
#   scripts/test.sh          the full suite (what CI runs)
#   scripts/test.sh --fast   the fast tier: what no marker of tests/tier_markers.py marks (slow, study, cluster, gui),
#                            still every layer: core, renderer, bindings, package, add-on in headless Blender
set -euo pipefail
cd "$(dirname "$0")/.."
fast=0
case "${1:-}" in
  --fast) fast=1 ;;
  "") ;;
  *) echo "usage: scripts/test.sh [--fast]" >&2; exit 2 ;;
esac
scripts/setup.sh
export PYTHONPATH="$PWD/build/python${PYTHONPATH:+:$PYTHONPATH}"
selection=()
if ((fast)); then
  selection=(-m "$(/usr/bin/python3 -c 'import sys; sys.path.insert(0, "tests"); import tier_markers; print(tier_markers.FAST_SELECTION)')")
fi
status=0
scripts/check_style.sh || status=1
ctest --test-dir build --output-on-failure -j"$(nproc)" || status=1
/usr/bin/python3 -m pytest -q -p no:cacheprovider "${selection[@]}" tests/python || status=1
blender -b --factory-startup --python-exit-code 1 --python tests/blender/run_tests.py -- -q "${selection[@]}" || status=1
exit $status
