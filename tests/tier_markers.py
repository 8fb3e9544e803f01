"""The test markers, registered by tests/python/conftest.py and tests/blender/conftest.py.  `scripts/test.sh --fast`
runs what none of them marks; `scripts/test.sh` runs everything."""

MARKERS = {
    "slow": "takes seconds: statistical tests with many samples, renders to convergence",
    "study": "runs the study (python -m sphrect.study) or its report end to end",
    "cluster": "starts a local Dask cluster",
    "gui": "opens Blender's window under Xvfb",
}
# What the fast tier leaves out (pytest -m).
FAST_SELECTION = " and ".join(f"not {m}" for m in MARKERS)


def register(config):
    for name, description in MARKERS.items():
        config.addinivalue_line("markers", f"{name}: {description}")
