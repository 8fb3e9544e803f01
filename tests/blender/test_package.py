"""The add-on zip carries its own copy of the native module and loads it without the repository."""
import os
import subprocess
import sys
import zipfile

import bpy

from conftest import REPO


def test_zip_add_on_loads_its_bundled_module(tmp_path):
    build_dir = os.path.dirname(os.environ["SPHRECT_PYTHON_PATH"].split(os.pathsep)[0])
    out = tmp_path / "sphrect_blender.zip"
    subprocess.run([sys.executable, os.path.join(REPO, "scripts", "package_addon.py"), "--build-dir", build_dir,
                    "--output", str(out)], check=True, env={**os.environ, "PYTHONNOUSERSITE": "1"})
    with zipfile.ZipFile(out) as z:
        names = z.namelist()
        z.extractall(tmp_path / "addons")
    assert "sphrect_blender/__init__.py" in names and "sphrect_blender/lib/sphrect/scene.py" in names
    assert any(n.startswith("sphrect_blender/lib/sphrect/_native") for n in names)
    # A fresh Blender without the repository's paths: the add-on must find the bundled copy.
    script = ("import sys, addon_utils; sys.path.insert(0, %r); addon_utils.enable('sphrect_blender', "
              "handle_error=None); import sphrect_blender; m = sphrect_blender.load_sphrect(); "
              "print('SPHRECT_FROM', m.__file__); sys.stdout.flush()") % str(tmp_path / "addons")
    env = {k: v for k, v in os.environ.items() if k not in ("SPHRECT_PYTHON_PATH", "PYTHONPATH")}
    run = subprocess.run([bpy.app.binary_path, "-b", "--factory-startup", "--python-exit-code", "1",
                          "--python-expr", script], capture_output=True, text=True, env=env, timeout=120)
    assert run.returncode == 0, run.stderr
    line = [l for l in run.stdout.splitlines() if l.startswith("SPHRECT_FROM")][0]
    assert line.split()[1].startswith(str(tmp_path / "addons" / "sphrect_blender" / "lib" / "sphrect"))
