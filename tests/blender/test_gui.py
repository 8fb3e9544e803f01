"""F12 and Esc in a real window: Blender with a (virtual) display, started under xvfb-run."""
import json
import os
import shutil
import subprocess

import bpy
import pytest

pytestmark = pytest.mark.gui


HERE = os.path.dirname(os.path.abspath(__file__))


@pytest.mark.skipif(shutil.which("xvfb-run") is None, reason="xvfb-run is not installed (apt install xvfb)")
def test_f12_compare_window_and_esc_cancel():
    run = subprocess.run(["xvfb-run", "-a", "-s", "-screen 0 1280x800x24", bpy.app.binary_path, "--factory-startup",
                          "--python", os.path.join(HERE, "gui_smoke.py")],
                         capture_output=True, text=True, timeout=180, env=dict(os.environ))
    lines = [l for l in run.stdout.splitlines() if l.startswith("GUI_RESULT ")]
    assert lines, run.stdout[-2000:] + run.stderr[-2000:]
    result = json.loads(lines[0][len("GUI_RESULT "):])
    assert "timeout" not in result, result
    assert result["compare_errors"] == [] and not result["compare_cancelled"]
    assert "SPHRECT Comparison" in result["editors"]  # opened in an Image Editor
    # ... fitted to it (View > Frame All): wholly inside the editor, and filling it in width or height.
    assert result["comparison_fit"], result
    for fit in result["comparison_fit"]:
        (w, h), (rw, rh) = fit["shown"], fit["region"]
        assert w <= rw + 1 and h <= rh + 1 and (w >= 0.8 * rw or h >= 0.8 * rh), fit
    assert result["cancelled"] and result["samples"] < 200000
    assert result["partial_max"] > 0  # the partial image is kept
