"""Builds the mm package with its own copy of mm's shared libraries (libmm_runtime, libmm_build)
in mm/_lib, so that it imports with only PYTHONPATH set.

The libraries come from MM_LIBRARY_DIR when it is set (a build tree or an installed lib/ folder:
the test suite's way, nothing is compiled), else they are built here with CMake from the
repository this folder is in (MM_SOURCE_DIR overrides where that is).
The version is the library's, read from include/mm/version.h.
"""
import glob
import os
import re
import shutil
import subprocess

from setuptools import setup
from setuptools.command.build_py import build_py

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.path.abspath(os.environ.get("MM_SOURCE_DIR") or os.path.join(HERE, ".."))
LIBRARIES = ("mm_runtime", "mm_build")


def version():
    with open(os.path.join(SOURCE, "include", "mm", "version.h"), encoding="utf-8") as f:
        text = f.read()
    parts = [re.search(r"^#define MM_VERSION_%s (\d+)$" % p, text, re.M).group(1) for p in ("MAJOR", "MINOR", "PATCH")]
    return ".".join(parts)


def built_libraries():
    """The folder holding libmm_runtime.so and libmm_build.so: MM_LIBRARY_DIR, or a CMake build."""
    given = os.environ.get("MM_LIBRARY_DIR")
    if given:
        return given
    build = os.path.join(HERE, "build", "cmake")
    subprocess.check_call(["cmake", "-S", SOURCE, "-B", build, "-DCMAKE_BUILD_TYPE=Release",
                           "-DMM_BUILD_TESTS=OFF", "-DMM_BUILD_BENCH=OFF"])
    subprocess.check_call(["cmake", "--build", build, "-j2", "--target", "mm_runtime_shared", "mm_build_shared"])
    return build


class BuildWithLibraries(build_py):
    def run(self):
        super().run()
        source = built_libraries()
        target = os.path.join(self.build_lib, "mm", "_lib")
        os.makedirs(target, exist_ok=True)
        for name in LIBRARIES:
            # the file the soname names (libmm_runtime.so.0.1), its contents the real library
            found = sorted(glob.glob(os.path.join(source, "lib%s.so.*" % name)), key=len)
            if not found:
                raise SystemExit("mm: no lib%s.so.* in %s (set MM_LIBRARY_DIR or build mm first)" % (name, source))
            shutil.copyfile(os.path.realpath(found[0]), os.path.join(target, os.path.basename(found[0])))


setup(version=version(), cmdclass={"build_py": BuildWithLibraries},
      package_data={"mm": ["_lib/*"]}, zip_safe=False)
