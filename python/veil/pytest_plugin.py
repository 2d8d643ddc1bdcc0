"""pytest fixtures for tests that render with Veil. In a conftest.py:

    pytest_plugins = ["veil.pytest_plugin"]

renderer: one veil.Renderer (one headless GL context) for the whole session.
"""

import pytest

import veil


@pytest.fixture(scope="session")
def renderer():
    return veil.Renderer()
