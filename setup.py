"""`pip install .`: CMake builds the native module (no tests, no benchmarks) and assembles the package in its build
folder's python/sphrect, which is what gets installed.  The build needs Debian's packages that scripts/setup.sh
installs (Embree, pybind11, OpenImageIO, a compiler, CMake)."""
import os
import subprocess
import sys

from setuptools import Distribution, find_packages, setup
from setuptools.command.build_py import build_py

ROOT = os.path.dirname(os.path.abspath(__file__))


class BuildWithCMake(build_py):
    def run(self):
        build_dir = os.path.join(ROOT, "build-pip")
        subprocess.check_call(["cmake", "-S", ROOT, "-B", build_dir, "-DCMAKE_BUILD_TYPE=Release",
                               f"-DPython3_EXECUTABLE={sys.executable}", "-DSPHRECT_BUILD_TESTS=OFF",
                               "-DSPHRECT_BUILD_BENCHMARKS=OFF"])
        subprocess.check_call(["cmake", "--build", build_dir, "-j", str(os.cpu_count() or 1)])
        super().run()  # the Python sources (python/sphrect)
        package = os.path.join(build_dir, "python", "sphrect")
        for name in os.listdir(package):
            if name.endswith(".so"):  # _native and the image reader it loads from beside itself
                self.copy_file(os.path.join(package, name), os.path.join(self.build_lib, "sphrect", name))


class NativeDistribution(Distribution):
    def has_ext_modules(self):  # the package holds a compiled module: a platform wheel
        return True


setup(packages=find_packages("python"), package_dir={"": "python"}, cmdclass={"build_py": BuildWithCMake},
      distclass=NativeDistribution)
