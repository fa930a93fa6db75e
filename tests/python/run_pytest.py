"""Runs one tests/python file with pytest for ctest; exits 77 (ctest: skipped) with the reason
when pytest or NumPy is missing (bash scripts/install-deps.sh installs python3-pytest and
python3-numpy for /usr/bin/python3)."""
import sys

for module, package in (("pytest", "python3-pytest"), ("numpy", "python3-numpy")):
    try:
        __import__(module)
    except ImportError:
        print("skipped: %s has no %s (Debian: apt-get install %s)" % (sys.executable, module, package))
        sys.exit(77)

import pytest

# -p no:cacheprovider: no .pytest_cache in the source tree.
sys.exit(pytest.main(["-q", "-p", "no:cacheprovider", *sys.argv[1:]]))
