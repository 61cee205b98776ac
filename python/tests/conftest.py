"""Shared fixtures of the Python package's tests."""

import signal

import pytest


@pytest.fixture
def ctrl_c():
    """Ctrl-C raises KeyboardInterrupt during the test, however the tests were started: a
    shell starting them in the background (`command &` without job control, as `nohup ... &`
    does) hands Python SIGINT ignored, and then a test that sends itself SIGINT to stop a
    long run would wait for the run to end (a sweep of a million runs: for hours)."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)
