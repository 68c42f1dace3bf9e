"""Runs one pytest file for ctest and tells ctest what happened: the pytest exit code, except
77 (the tests' SKIP_RETURN_CODE) when nothing failed but a test was skipped, so that a file whose
tests were skipped is reported as skipped, never as passed. Usage: run_pytest.py FILE"""
import sys

import pytest


class Skips:
    def __init__(self):
        self.reasons = []

    def pytest_runtest_logreport(self, report):
        if report.skipped:
            why = report.longrepr[-1] if isinstance(report.longrepr, tuple) else report.longrepr
            self.reasons.append(f"{report.nodeid}: {why}")


def main():
    skips = Skips()
    args = ["-q", "-rs", "-p", "no:cacheprovider", *sys.argv[1:]]
    code = int(pytest.main(args, plugins=[skips]))
    if code == 0 and skips.reasons:
        print(f"run_pytest: {len(skips.reasons)} skipped; reported to ctest as skipped:")
        for reason in skips.reasons:
            print(f"  {reason}")
        return 77
    return code


if __name__ == "__main__":
    sys.exit(main())
