"""Runs pytest on the Python module's tests for ctest (tests/python/CMakeLists.txt).

Exits 77, which ctest counts as skipped, with the reason when pytest or numpy is missing.
"""

import sys

try:
    import pytest
except ImportError:
    print(f"skipped: pytest is not installed for {sys.executable} (Debian: apt-get install python3-pytest)")
    sys.exit(77)
try:
    import numpy  # noqa: F401
except ImportError:
    print(f"skipped: numpy is not installed for {sys.executable} (Debian: apt-get install python3-numpy)")
    sys.exit(77)

sys.exit(pytest.main(["-q", "-rs", "-p", "no:cacheprovider", *sys.argv[1:]]))
