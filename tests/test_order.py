"""The files `make test` hands out first and last (tests/conftest.py's LONG_FILES_FIRST and
LAST_FILES) are test files that exist, each named once: a file renamed or moved would otherwise
lose its place in silence and the run's order with it."""

from tests.conftest import LAST_FILES, LONG_FILES_FIRST, TESTS


def test_every_placed_file_exists_and_is_placed_once():
    placed = [*LONG_FILES_FIRST, *LAST_FILES]
    assert len(placed) == len(set(placed)), [name for name in placed if placed.count(name) > 1]
    missing = [
        name for name in placed if not (TESTS / name).is_file() or not name.rpartition("/")[2].startswith("test_")
    ]
    assert not missing, missing
