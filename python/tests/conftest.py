import os
import pathlib

import pytest

SOURCE = pathlib.Path(os.environ.get("NHC_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))


@pytest.fixture
def source():
    """The repository's top directory (examples/, tests/bad/)."""
    return SOURCE
