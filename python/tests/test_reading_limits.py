"""Reading has limits (docs/safety.md): nhc.Scene.load refuses, before reading a byte, what is
not a regular file or is larger than 64 MB, with nhc.SceneError naming the file (it used to read
/dev/zero until the machine ran out of memory)."""
import os
import resource
import time

import pytest

import nhc


@pytest.fixture(autouse=True)
def bounded_memory():
    """A regression reads /dev/zero: let it fail at 4 GB of address space, not take the machine."""
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    resource.setrlimit(resource.RLIMIT_AS, (4 << 30, hard))
    yield
    resource.setrlimit(resource.RLIMIT_AS, (soft, hard))


def test_devices_directories_and_fifos_are_refused_at_once(tmp_path):
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    for path, kind in (("/dev/zero", "a character device"), (str(tmp_path), "a directory"), (str(fifo), "a FIFO")):
        start = time.monotonic()
        with pytest.raises(nhc.SceneError, match=f"^{path}: error: is {kind}, not a scene file$"):
            nhc.Scene.load(path)
        assert time.monotonic() - start < 5


def test_a_scene_larger_than_64_mb_is_refused(tmp_path):
    big = tmp_path / "big.toml"
    with open(big, "wb") as f:
        f.truncate(65 << 20)  # sparse: nothing written
    with pytest.raises(nhc.SceneError, match="big.toml: error: is 65 MB, more than the 64 MB nhc reads as a scene file"):
        nhc.Scene.load(str(big))
