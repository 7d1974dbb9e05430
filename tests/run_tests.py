#!/usr/bin/env python3
"""fsiopt test suite: every test asserts a property (a convergence rate, agreement
between runs, a solver count, a clean refusal of bad input). Run by `make test` (all) and
`make test-quick` (the fast tier).

  tests/run_tests.py [--quick] [WORD...]

--quick: only the fast tier (tests registered with quick=True); WORD: only the tests whose
title or function name contains one of the words. One line per test; last line
'N passed, M failed'; exit status 1 on any failure. The tests are in tests/test_*.py, one
file per area, on the harness of tests/harness.py."""
import os, sys

sys.dont_write_bytecode = True   # no tests/__pycache__
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import harness  # noqa: E402
import test_solvers, test_coupling, test_moving_meshes, test_fields, test_scenes, test_reliability, test_bad_input, test_options, test_operators, test_defaults, test_partitioned  # noqa: E402,F401  (they register their tests)

if __name__ == "__main__":
    sys.exit(harness.main(sys.argv[1:]))
