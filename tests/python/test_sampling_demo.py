"""The sampling demo (the project's main job until the renderer exists) runs and writes its PNG."""
import importlib.util
import os

import numpy as np

DEMO = os.path.join(os.path.dirname(__file__), "..", "..", "scripts", "sampling_demo.py")


def _load_demo():
    spec = importlib.util.spec_from_file_location("sampling_demo", DEMO)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_demo_writes_a_png(tmp_path):
    demo = _load_demo()
    path = demo.main(["--out", str(tmp_path / "out"), "--n", "64"])
    assert os.path.basename(path) == "sampling_demo.png"
    import matplotlib.image
    image = matplotlib.image.imread(path)
    assert image.ndim == 3 and image.shape[0] > 300 and image.shape[1] > 1000
    assert np.std(image[..., :3]) > 0.01   # not a blank canvas


def test_demo_projection_is_equal_area():
    """The sphere view must be area-preserving for its claim (uniform in solid angle looks uniform)
    to hold: the Lambert projection's Jacobian, by finite differences, is 1 per steradian."""
    demo = _load_demo()
    centre = demo.CORNER + 0.5 * (demo.EDGE_X + demo.EDGE_Y)
    w = centre / np.linalg.norm(centre)
    a = np.cross(w, [0.0, 1.0, 0.0])
    a /= np.linalg.norm(a)
    b = np.cross(w, a)
    eps = 1e-5
    for theta, phi in [(0.3, 0.2), (1.0, 2.0), (2.0, -1.0)]:
        def direction(t, p):
            return np.cos(t) * w + np.sin(t) * (np.cos(p) * a + np.sin(p) * b)
        xy = lambda t, p: demo.equal_area_projection(direction(t, p)[None, :])[0]  # noqa: E731
        dt = (xy(theta + eps, phi) - xy(theta - eps, phi)) / (2 * eps)
        dp = (xy(theta, phi + eps) - xy(theta, phi - eps)) / (2 * eps)
        jacobian = abs(dt[0] * dp[1] - dt[1] * dp[0])
        assert abs(jacobian - np.sin(theta)) < 1e-6     # d omega = sin(theta) d theta d phi
