"""What the tests run on, from the environment tests/test_python.sh sets up:
MM_TEST_DB (a database of the built-in set), MM_TEST_DATA (the built-in set's BVH files, for
building), MM_CLI (the mm program, for comparing with it), MM_SOURCE_DIR (the repository)."""
import os

import pytest


def _env(name):
    value = os.environ.get(name)
    if not value:
        pytest.skip("%s is not set (tests/test_python.sh sets it)" % name)
    return value


@pytest.fixture(scope="session")
def db_path():
    return _env("MM_TEST_DB")


@pytest.fixture(scope="session")
def db(db_path):
    import mm

    return mm.Database(db_path)


@pytest.fixture(scope="session")
def source_dir():
    return _env("MM_SOURCE_DIR")


@pytest.fixture(scope="session")
def data_dir():
    return _env("MM_TEST_DATA")


@pytest.fixture(scope="session")
def cli():
    return _env("MM_CLI")
