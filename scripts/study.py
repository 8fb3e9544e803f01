#!/usr/bin/python3
"""The comparative study in one command:

    scripts/study.py blend_scenes/01_paper.blend --out out/study [--resolution 320x180 --max-samples 256 ...]

Exports the .blend with Blender headless (or takes a .sphrect.npz), measures every light-sampling technique's
error against time (and Cycles 3.4's), and writes out/study/report.html and report.md. Run it again to resume.
Options: scripts/study.py --help. Uses the package built in build/python (scripts/setup.sh builds it) and,
for Blender, this repository's add-on (its headless entry point, unless $SPHRECT_BLENDER_SCRIPT names another).
"""
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BUILD = os.environ.get("SPHRECT_PYTHON_PATH", os.path.join(ROOT, "build", "python"))
sys.path.insert(0, BUILD)
os.environ.setdefault("SPHRECT_BLENDER_SCRIPT", os.path.join(ROOT, "addon", "sphrect_blender", "headless.py"))

from sphrect.study.cli import main  # noqa: E402

if __name__ == "__main__":
    sys.exit(main())
