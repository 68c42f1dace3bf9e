"""Input of check_runner.py: a test that fails and one that skips."""
import pytest


def test_fails():
    assert 1 + 1 == 3


def test_skips():
    pytest.skip("skipped on purpose")
