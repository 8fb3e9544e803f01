"""`pip install .` (setup.py: CMake builds the native module) into a fresh virtual environment, then `import sphrect`
there without PYTHONPATH renders a scene: the install a README reader does, with no network (--no-index) and
Debian's numpy (--system-site-packages)."""
import os
import subprocess
import sys

import pytest

pytestmark = pytest.mark.slow

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

RENDER = """
import numpy as np, sphrect
floor = sphrect.Mesh(vertices=np.array([[-4, -4, 0], [4, -4, 0], [4, 4, 0], [-4, 4, 0]], np.float32),
                     triangles=np.array([[0, 1, 2], [0, 2, 3]], np.int32))
light = sphrect.RectLight.from_power(center=(0, 0, 1), edge_x=(1, 0, 0), edge_y=(0, -0.5, 0), power=50)
camera = sphrect.Camera(width=8, height=6, to_world=[[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 6], [0, 0, 0, 1]])
image = sphrect.render(sphrect.Scene(camera=camera, meshes=[floor], lights=[light]), samples=2)["rectangle"]
print(sphrect.__file__)
print(float(image[..., :3].mean()))
"""


def test_pip_install_into_a_virtual_environment(tmp_path):
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", str(venv)], check=True)
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    subprocess.run([str(venv / "bin" / "pip"), "install", "--no-index", "--no-build-isolation", "--no-deps", "-q",
                    REPO], check=True, env=env, cwd=tmp_path)
    out = subprocess.run([str(venv / "bin" / "python"), "-c", RENDER], check=True, env=env, cwd=tmp_path,
                         capture_output=True, text=True).stdout.split()
    assert out[0].startswith(str(venv))  # the installed copy, not the source tree or build/python
    assert float(out[1]) > 0
