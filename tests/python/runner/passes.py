"""Input of check_runner.py: a test that passes."""


def test_passes():
    assert 2 * 2 == 4
