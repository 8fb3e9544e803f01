"""Shared pytest set-up for the Python tests: keep this small (several test files share it)."""
import os
import sys

# Tests run against the built package (build/python); PYTHONPATH set by scripts/test.sh wins.
try:
    import sphrect  # noqa: F401
except ImportError:
    sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "build", "python"))

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))
import tier_markers  # noqa: E402  (tests/tier_markers.py: the markers both suites register)


def pytest_configure(config):
    tier_markers.register(config)
