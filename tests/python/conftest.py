"""Shared fixtures of the Python tests: the vpm tool built beside the module (VPM_BINARY, set by
ctest) and the source tree's configs (VPM_SOURCE_DIR)."""
import os
import subprocess

import pytest

SOURCE_DIR = os.environ.get("VPM_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
FURNACE = os.path.join(SOURCE_DIR, "configs", "uniform_furnace.toml")
# Small enough for a test, large enough for a photon pass with thousands of stored photons.
SMALL = {"render.width": 24, "render.height": 16, "render.spp": 2, "photons.count": 20000, "render.seed": 7}


def tool_overrides(overrides):
    """The --set arguments of the same overrides (vpm's own formatting of Python values)."""
    import vpm
    return [a for k, v in overrides.items() for a in ("--set", "%s=%s" % (k, vpm._toml_value(v, k)))]


@pytest.fixture(scope="session")
def vpm_binary():
    path = os.environ.get("VPM_BINARY")
    if not path or not os.path.exists(path):
        pytest.skip("VPM_BINARY is not set to the built vpm tool (ctest sets it)")
    return path


def run_tool(binary, *args):
    """Runs the tool; returns (exit code, stderr)."""
    p = subprocess.run([binary, *args], capture_output=True, text=True)
    return p.returncode, p.stderr
