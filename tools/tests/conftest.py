"""pytest configuration for the reference and command-line tests."""


def pytest_configure(config):
    config.addinivalue_line("markers", "slow: runs for seconds (recovery sweeps, many seeds)")
