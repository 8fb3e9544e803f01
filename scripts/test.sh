#!/bin/bash
# All tests: C++ (ctest/GoogleTest), Python (pytest on the module), Blender (pytest inside headless Blender).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
export PYTHONPATH="$PWD/build/python${PYTHONPATH:+:$PYTHONPATH}"
status=0
ctest --test-dir build --output-on-failure -j"$(nproc)" || status=1
/usr/bin/python3 -m pytest -q -p no:cacheprovider tests/python || status=1
if [ -f tests/blender/run_tests.py ]; then
  blender -b --factory-startup --python-exit-code 1 --python tests/blender/run_tests.py -- -q || status=1
fi
exit $status
