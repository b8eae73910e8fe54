"""Builds the compiled part of the `freeform` package with CMake (pyproject.toml holds the rest).

The module is built in build/wheel (FREEFORM_WHEEL_BUILD_DIR overrides) with the release preset's
flags, so ccache reuses the objects of a release build, then made self-contained: the shared
libraries it needs are copied into freeform/_libs with $ORIGIN run paths (python/bundle_libs.py).
"""
import os
import pathlib
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(ROOT / "python"))
import bundle_libs  # noqa: E402


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build = pathlib.Path(os.environ.get("FREEFORM_WHEEL_BUILD_DIR", ROOT / "build" / "wheel"))
        env = dict(os.environ, CCACHE_BASEDIR=os.environ.get("CCACHE_BASEDIR", str(ROOT)), CCACHE_NOHASHDIR="1")
        configure = ["cmake", "-S", str(ROOT), "-B", str(build), "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release",
                     "-DFREEFORM_WERROR=ON", "-DFREEFORM_BUILD_TESTS=OFF", "-DFREEFORM_BUILD_BENCH=OFF",
                     "-DFREEFORM_BUILD_VIEWER=OFF", "-DFREEFORM_BUILD_EDITOR=OFF",
                     f"-DPython3_EXECUTABLE={sys.executable}"]
        subprocess.run(configure, check=True, env=env)
        subprocess.run(["cmake", "--build", str(build), "--target", "freeform_python"], check=True, env=env)
        built = next((build / "python" / "freeform").glob("_freeform*.so"))
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built, target)
        copies = bundle_libs.bundle(target)
        print(f"freeform: bundled {len(copies)} libraries into {target.parent / bundle_libs.LIB_DIR}")


setup(ext_modules=[Extension("freeform._freeform", sources=[])], cmdclass={"build_ext": CMakeBuild})
