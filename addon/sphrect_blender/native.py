"""Finding and importing the `sphrect` Python package (the native renderer).

Search order: an importable `sphrect` already on sys.path; $SPHRECT_PYTHON_PATH (os.pathsep-separated
directories that contain the `sphrect` package); the copy bundled in the add-on zip (`<add-on>/lib`);
the repository's default build directory (`<repo>/build/python`).
"""
import importlib
import os
import sys

ENV_VAR = "SPHRECT_PYTHON_PATH"
_ADDON_DIR = os.path.dirname(os.path.abspath(__file__))


def candidate_dirs():
    dirs = [d for d in os.environ.get(ENV_VAR, "").split(os.pathsep) if d]
    dirs.append(os.path.join(_ADDON_DIR, "lib"))
    dirs.append(os.path.normpath(os.path.join(_ADDON_DIR, "..", "..", "build", "python")))
    return dirs


def load_sphrect():
    """Import and return the `sphrect` module; ImportError with the places searched when it is missing
    or cannot be loaded (wrong Python version, missing Embree, ...)."""
    if "sphrect" in sys.modules:
        return sys.modules["sphrect"]
    searched = []
    for d in candidate_dirs():
        if os.path.isdir(os.path.join(d, "sphrect")):
            if d not in sys.path:
                sys.path.insert(0, d)
            break
        searched.append(d)
    try:
        return importlib.import_module("sphrect")
    except ImportError as e:
        sys.modules.pop("sphrect", None)
        raise ImportError(
            f"SPHRECT: the native module 'sphrect' could not be loaded ({e}). Build it "
            f"(cmake -S . -B build && cmake --build build) or set {ENV_VAR} to the directory holding the "
            f"'sphrect' package. Searched: {', '.join(searched) or 'sys.path'}") from e
