#!/usr/bin/env python3
"""Package the Blender add-on as an installable zip that carries its own copy of the sphrect package
(native module included), for Edit > Preferences > Add-ons > Install:

    python3 scripts/package_addon.py [--build-dir build] [--output dist/sphrect_blender.zip]

The zip holds `sphrect_blender/` with the package under `sphrect_blender/lib/sphrect/`, where the
add-on looks for it (see addon/sphrect_blender/native.py). The native module is built for Python 3.11
and links the system's Embree and Highway, so the zip installs into Debian's Blender 3.4 on a machine with
libembree3 and libhwy1 installed."""
import argparse
import glob
import os
import sys
import zipfile

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SKIP_DIRS = {"__pycache__"}
SKIP_SUFFIXES = (".pyc", ".pyo")


def _files(root, skip_dirs=SKIP_DIRS):
    for d, dirs, files in os.walk(root):
        dirs[:] = sorted(x for x in dirs if x not in skip_dirs)
        for f in sorted(files):
            if not f.endswith(SKIP_SUFFIXES):
                yield os.path.join(d, f)


def package(build_dir, output):
    addon = os.path.join(REPO, "addon", "sphrect_blender")
    package_dir = os.path.join(build_dir, "python", "sphrect")
    if not glob.glob(os.path.join(package_dir, "_native*.so")):
        raise SystemExit(f"no native module in {package_dir}: build first (cmake --build {build_dir})")
    os.makedirs(os.path.dirname(os.path.abspath(output)), exist_ok=True)
    with zipfile.ZipFile(output, "w", zipfile.ZIP_DEFLATED) as z:
        for path in _files(addon, SKIP_DIRS | {"lib"}):  # (a lib/ left in the source tree is not shipped)
            z.write(path, os.path.join("sphrect_blender", os.path.relpath(path, addon)))
        for path in _files(package_dir):
            z.write(path, os.path.join("sphrect_blender", "lib", "sphrect", os.path.relpath(path, package_dir)))
    return output


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--build-dir", default=os.path.join(REPO, "build"))
    p.add_argument("--output", default=os.path.join(REPO, "dist", "sphrect_blender.zip"))
    args = p.parse_args(argv)
    print(package(os.path.abspath(args.build_dir), args.output))


if __name__ == "__main__":
    sys.exit(main())
