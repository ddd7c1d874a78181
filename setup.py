"""Builds the Python package hemivem through CMake (pyproject.toml; python/README.md).

    python3 -m pip install --no-build-isolation .

The module is built by CMake in the folder HEMIVEM_BUILD_DIR when that variable names one
(a build of this checkout, e.g. the ./build of scripts/build.sh: only what is missing is
built), else in ./build-pip, configured on first use (Release, Ninja when found). CMake then
installs the build into a staging folder (./build-pip/stage), from which the package takes python/hemivem's files,
the compiled module _hemivem and the hemivem libraries it loads (found beside the module
through its run path), so that the installed package needs no build folder.
"""

import os
import pathlib
import re
import shutil
import subprocess
import sys
import sysconfig

from setuptools import Distribution, setup
from setuptools.command.build_py import build_py

ROOT = pathlib.Path(__file__).resolve().parent


def version():
    text = (ROOT / "CMakeLists.txt").read_text()
    return re.search(r"project\(hemivem VERSION ([0-9.]+)", text).group(1)


def run(command, what):
    print("hemivem setup.py:", " ".join(str(c) for c in command), flush=True)
    try:
        subprocess.run([str(c) for c in command], check=True)
    except FileNotFoundError as e:
        raise SystemExit(f"hemivem setup.py: {what}: {e.filename} not found (Debian: cmake)") from None
    except subprocess.CalledProcessError as e:
        raise SystemExit(f"hemivem setup.py: {what} failed (exit status {e.returncode}); see the lines above") from None


def cache_value(build, name):
    for line in (build / "CMakeCache.txt").read_text().splitlines():
        if line.startswith(name + ":"):
            return line.split("=", 1)[1]
    return None


def cmake_build_folder():
    """The CMake build folder: HEMIVEM_BUILD_DIR, or ./build-pip configured on first use."""
    given = os.environ.get("HEMIVEM_BUILD_DIR")
    if given:
        build = pathlib.Path(given).resolve()
        if not (build / "CMakeCache.txt").is_file():
            raise SystemExit(f"hemivem setup.py: HEMIVEM_BUILD_DIR={given}: not a CMake build folder "
                             "(no CMakeCache.txt); configure it with scripts/build.sh, or unset it")
        source = cache_value(build, "CMAKE_HOME_DIRECTORY")
        if source and pathlib.Path(source).resolve() != ROOT:
            raise SystemExit(f"hemivem setup.py: HEMIVEM_BUILD_DIR={given} builds {source}, not {ROOT}")
        return build
    build = ROOT / "build-pip"
    if not (build / "CMakeCache.txt").is_file():
        generator = ["-G", "Ninja"] if shutil.which("ninja") else []
        run(["cmake", "-S", ROOT, "-B", build, *generator, "-DCMAKE_BUILD_TYPE=Release",
             "-DHEMIVEM_BUILD_BENCHMARKS=OFF", f"-DPython3_EXECUTABLE={sys.executable}"], "configuring CMake")
    return build


class BuildWithCMake(build_py):
    """build_py, then the compiled module and the libraries it loads from a CMake install."""

    def run(self):
        super().run()
        build = cmake_build_folder()
        jobs = str(os.cpu_count() or 1)
        run(["cmake", "--build", build, "--parallel", jobs, "--target", "hemivem_product"], "building with CMake")
        suffix = sysconfig.get_config_var("EXT_SUFFIX")
        built = list((build / "python" / "hemivem").glob("_hemivem*.so"))
        if not built:
            raise SystemExit(f"hemivem setup.py: {build} has no Python module: CMake did not find pybind11, "
                             "Python's headers or NumPy (Debian: pybind11-dev python3-dev python3-numpy); "
                             "its configure summary says which")
        if not any(m.name == "_hemivem" + suffix for m in built):
            raise SystemExit(f"hemivem setup.py: the module in {build} ({built[0].name}) is not for this "
                             f"Python ({sys.executable}, modules *{suffix}); build with "
                             f"-DPython3_EXECUTABLE={sys.executable}")
        stage = ROOT / "build-pip" / "stage"
        shutil.rmtree(stage, ignore_errors=True)
        for component in ("Unspecified", "hemivem_python"):
            run(["cmake", "--install", build, "--prefix", stage, "--component", component], "installing with CMake")
        package = next(stage.rglob("hemivem/_hemivem" + suffix)).parent
        target = pathlib.Path(self.build_lib) / "hemivem"
        target.mkdir(parents=True, exist_ok=True)
        shutil.copy2(package / ("_hemivem" + suffix), target)
        # the libraries by the names the module and each other ask for (their sonames)
        for library in stage.rglob("libhemivem*.so.*"):
            if re.fullmatch(r"libhemivem\w*\.so\.\d+", library.name):
                shutil.copy2(library, target / library.name, follow_symlinks=True)


class BinaryDistribution(Distribution):
    """A package with a compiled module: its wheel is for this platform and Python."""

    def has_ext_modules(self):
        return True


setup(
    version=version(),
    packages=["hemivem"],
    package_dir={"hemivem": "python/hemivem"},
    package_data={"hemivem": ["__init__.pyi", "py.typed"]},
    cmdclass={"build_py": BuildWithCMake},
    distclass=BinaryDistribution,
    options={"build": {"build_base": "build-pip/setuptools"}},
)
