"""Run the add-on's tests inside headless Blender:

    blender -b --factory-startup --python-exit-code 1 --python tests/blender/run_tests.py -- [pytest args]

Puts the repository's `addon/` and the sphrect package directory ($SPHRECT_PYTHON_PATH, default
`build/python`) on sys.path, enables the add-on, runs pytest on tests/blender and exits with its status."""
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
PACKAGE_DIR = os.environ.get("SPHRECT_PYTHON_PATH") or os.path.join(REPO, "build", "python")
os.environ["SPHRECT_PYTHON_PATH"] = PACKAGE_DIR  # also for sub-processes and the add-on's own lookup

for path in (os.path.join(REPO, "addon"), PACKAGE_DIR.split(os.pathsep)[0]):
    if path not in sys.path:
        sys.path.insert(0, path)


def main():
    import addon_utils
    import pytest
    addon_utils.enable("sphrect_blender", default_set=True, handle_error=None)
    args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    code = pytest.main([HERE, "--rootdir", HERE, "-p", "no:cacheprovider", *args])
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(int(code))  # Blender would otherwise exit 0


main()
