#!/bin/bash
# The main job: set up, then render the paper's scene with every technique and write the comparison to out/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
export PYTHONPATH="$PWD/build/python${PYTHONPATH:+:$PYTHONPATH}"
mkdir -p out
/usr/bin/python3 scripts/sampling_demo.py --out out
if [ -f scripts/render_paper_scene.py ]; then
  /usr/bin/python3 scripts/render_paper_scene.py --out out
fi
echo "Results in $PWD/out"
