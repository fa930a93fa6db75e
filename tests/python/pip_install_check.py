"""`pip install .` of the source tree into a fresh virtual environment, then `import vpm` and a
small render there (ctest Python.PipInstall, the Python route of docs/python.md).

Exits 77 (ctest: skipped) with the reason when the Python package index cannot be reached (pip
fetches scikit-build-core, pybind11 and NumPy from it) or the interpreter cannot make a venv.
The build folder is kept between runs, and the compiler is the CMake build's, so that ccache and
ninja make a rerun cheap.

    python3 pip_install_check.py --source DIR --venv DIR --build-dir DIR [--cxx COMPILER]
"""
import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request

SKIP = 77


def index_url():
    """The index pip would use: PIP_INDEX_URL, else pip's configured index-url, else PyPI."""
    url = os.environ.get("PIP_INDEX_URL")
    if not url:
        try:
            out = subprocess.run([sys.executable, "-m", "pip", "config", "get", "global.index-url"],
                                 capture_output=True, text=True, timeout=30)
            url = out.stdout.strip() if out.returncode == 0 else ""
        except (OSError, subprocess.TimeoutExpired):
            url = ""
    return (url or "https://pypi.org/simple").rstrip("/")


def index_unreachable(url):
    """None when the index answers for scikit-build-core, else the reason."""
    try:
        with urllib.request.urlopen(url + "/scikit-build-core/", timeout=20) as response:
            response.read(1)
        return None
    except (urllib.error.URLError, OSError) as e:
        return "%s: %s" % (url, getattr(e, "reason", e))


def build_requirements(pyproject):
    """[build-system] requires of pyproject.toml."""
    import tomllib   # Python 3.11
    with open(pyproject, "rb") as f:
        return list(tomllib.load(f)["build-system"]["requires"])


CHECK = r"""
import os, sys
import numpy
import vpm
venv = os.path.realpath(sys.prefix)
where = os.path.realpath(vpm.__file__)
assert where.startswith(venv + os.sep), "vpm imported from %s, not from the venv %s" % (where, venv)
config = vpm.load_config(os.path.join(sys.argv[1], "configs", "uniform_furnace.toml"),
                         overrides={"render.width": 8, "render.height": 8, "render.spp": 1, "photons.count": 2000})
result = vpm.render(config, threads=1, progress=False)
assert result.image.shape == (8, 8, 3) and result.image.dtype == numpy.float32, result.image.shape
assert numpy.isfinite(result.image).all() and result.image.mean() > 0
print("vpm %s from %s: rendered %s, mean %.3f" % (vpm.__version__, where, result.image.shape, result.image.mean()))
"""


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--source", required=True)
    parser.add_argument("--venv", required=True)
    parser.add_argument("--build-dir", required=True)
    parser.add_argument("--cxx", default="")
    args = parser.parse_args()

    url = index_url()
    reason = index_unreachable(url)
    if reason:
        print("skipped: the Python package index is unreachable (%s); pip install . needs it for "
              "scikit-build-core, pybind11 and NumPy" % reason)
        return SKIP

    shutil.rmtree(args.venv, ignore_errors=True)
    made = subprocess.run([sys.executable, "-m", "venv", args.venv], capture_output=True, text=True)
    if made.returncode != 0:
        print("skipped: %s cannot make a virtual environment (Debian: apt-get install python3-venv):\n%s"
              % (sys.executable, made.stderr.strip()))
        return SKIP
    python = os.path.join(args.venv, "bin", "python")

    env = dict(os.environ, PIP_DISABLE_PIP_VERSION_CHECK="1", CMAKE_BUILD_PARALLEL_LEVEL="2")
    env.pop("PYTHONPATH", None)
    if args.cxx:
        env["CXX"] = args.cxx   # the CMake build's compiler: the same ccache entries

    def pip(what, *pip_args):
        start = time.monotonic()
        done = subprocess.run([python, "-m", "pip", "install", "--quiet", *pip_args], capture_output=True,
                              text=True, env=env)
        seconds = time.monotonic() - start
        if done.returncode != 0:
            print("pip install %s failed (exit %d, %.0f s):\n%s\n%s" % (what, done.returncode, seconds,
                                                                        done.stdout[-4000:], done.stderr[-4000:]))
        else:
            print("pip install %s: %.0f s" % (what, seconds))
        return done.returncode == 0

    # The build requirements pyproject.toml declares, installed into the venv first and the build run
    # there (--no-build-isolation): pip's isolated build would put pybind11's headers under a new
    # temporary path each time, and every module source would be compiled again.
    try:
        requires = build_requirements(os.path.join(args.source, "pyproject.toml"))
    except ImportError:
        print("skipped: %s has no tomllib (Python 3.11) to read pyproject.toml" % sys.executable)
        return SKIP
    if not pip(" ".join(requires), *requires):
        return 1
    if not pip(args.source, "--no-build-isolation", args.source, "--config-settings=build-dir=" + args.build_dir):
        return 1

    with tempfile.TemporaryDirectory() as cwd:   # not the source tree: import what pip installed
        check = subprocess.run([python, "-c", CHECK, os.path.abspath(args.source)], capture_output=True,
                               text=True, env=env, cwd=cwd)
    sys.stdout.write(check.stdout)
    if check.returncode != 0:
        print("import vpm from the venv failed:\n%s" % check.stderr[-4000:])
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
