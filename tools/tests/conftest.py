"""pytest configuration and shared fixtures of the reference and
command-line tests. The helpers live in the installed package pdtsupport
(pip install -e tools), never in another test module."""
import pathlib

import pytest

from pdtsupport import cli, status

ROOT = pathlib.Path(__file__).resolve().parents[2]


def pytest_configure(config):
    config.addinivalue_line("markers", "slow: runs for seconds (recovery sweeps, many seeds)")
    config.addinivalue_line("markers", "cli: runs the pdtfit program (skipped without one, "
                            "failed when CI=true or PDTFIT_REQUIRE_BIN=1)")


def pytest_runtest_setup(item):
    cli.setup_cli_test(item)


@pytest.fixture(scope="session")
def root():
    """The checkout's root directory."""
    return ROOT


@pytest.fixture(scope="session")
def vectors_dir():
    """tests/vectors/, the generated C test vectors."""
    return ROOT / "tests" / "vectors"


@pytest.fixture(scope="session")
def pdt_status():
    """{name: value} of pdt_status_t, read from the C header."""
    return dict(status.STATUS)
