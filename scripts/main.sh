#!/bin/bash
# The main job: set up, then render the paper's scene with every technique and write the comparison to out/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
export PYTHONPATH="$PWD/build/python${PYTHONPATH:+:$PYTHONPATH}"
mkdir -p out
# 1. The warps themselves: Hammersley points mapped onto a light by each technique.
/usr/bin/python3 scripts/sampling_demo.py --out out
# 2. The paper's scene, built in Python: every technique, without and with MIS, against a reference.
/usr/bin/python3 scripts/render_paper_scene.py --out out
# 3. The same comparison through the Blender add-on, on blend_scenes/01_paper.blend (compare mode).
blender -b --factory-startup \
  --python-expr "import sys; sys.path.insert(0, 'addon'); import addon_utils; addon_utils.enable('sphrect_blender')" \
  blend_scenes/01_paper.blend \
  --python-expr "import bpy; bpy.context.scene.sphrect.compare = True" \
  -o "$PWD/out/blender_paper_" -F OPEN_EXR_MULTILAYER -f 1
echo "Results in $PWD/out: sampling_demo.png, paper_compare.png, paper_figures.json, blender_paper_0001_sphrect_compare.png"
