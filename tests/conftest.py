"""Suite-wide settings: the slowest tests start first.

`make test` runs the suite on two xdist workers. A test of a minute that starts
last keeps one worker busy while the other idles, so tests marked ``heavy``
(the end-to-end runs with video, the README commands, the local cluster, the long
regression demonstrations) are moved to the front of the collection; the rest keep
their order. Mark a test ``heavy`` when `pytest --durations` shows it above ~15 s.
"""

import pytest


def pytest_configure(config: pytest.Config) -> None:
    config.addinivalue_line("markers", "heavy: a slow test, scheduled before the others")


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    items.sort(key=lambda item: item.get_closest_marker("heavy") is None)  # stable sort
