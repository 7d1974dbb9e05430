#!/usr/bin/env python3
"""fsiopt test suite: every test asserts a property (a convergence rate, agreement
between runs, a solver count, a clean refusal of bad input). Run by `make test` (all) and
`make test-quick` (the fast tier).

  tests/run_tests.py [--quick] [--list] [WORD...]

--quick: only the fast tier (tests registered with quick=True); WORD: only the tests whose
title or function name contains one of the words; --list: the selected tests' names and
titles, without running them. One line per test; last line 'N passed, M failed'; exit
status 1 on any failure. The tests are in tests/test_*.py, one file per area, imported
here in the order of their file names (a new file needs no edit here); within a file they
run in the order they are written. The harness is tests/harness.py."""
import glob, importlib, os, sys

sys.dont_write_bytecode = True   # no tests/__pycache__
HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import harness  # noqa: E402


def import_test_modules():
    """Imports every tests/test_*.py (they register their tests), sorted by file name."""
    for path in sorted(glob.glob(os.path.join(HERE, "test_*.py"))):
        importlib.import_module(os.path.splitext(os.path.basename(path))[0])


import_test_modules()

if __name__ == "__main__":
    sys.exit(harness.main(sys.argv[1:]))
