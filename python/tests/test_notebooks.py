"""The example notebooks (examples/notebooks) run top to bottom with nbclient, as a reader's
Jupyter would: an error in any cell, an assert of the notebook's own checks included, fails."""
import pathlib

import pytest

from conftest import SOURCE

NOTEBOOKS = sorted((SOURCE / "examples" / "notebooks").glob("*.ipynb"))


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.stem for p in NOTEBOOKS])
def test_notebook_runs(path: pathlib.Path):
    nbformat = pytest.importorskip("nbformat", reason="Debian python3-nbformat (with python3-nbclient) is missing")
    nbclient = pytest.importorskip("nbclient", reason="Debian python3-nbclient is missing")
    pytest.importorskip("ipykernel", reason="Debian python3-ipykernel is missing")
    pytest.importorskip("matplotlib", reason="Debian python3-matplotlib is missing")
    pytest.importorskip("scipy", reason="Debian python3-scipy is missing (control_lqr)")
    pytest.importorskip("sympy", reason="Debian python3-sympy is missing (rigid_body)")
    notebook = nbformat.read(path, as_version=4)
    client = nbclient.NotebookClient(notebook, timeout=600, kernel_name="python3",
                                     resources={"metadata": {"path": str(path.parent)}})
    client.execute()  # raises CellExecutionError with the cell and its traceback
    errors = [o for cell in notebook.cells if cell.cell_type == "code" for o in cell.get("outputs", [])
              if o.get("output_type") == "error"]
    assert not errors
    images = [o for cell in notebook.cells if cell.cell_type == "code" for o in cell.get("outputs", [])
              if "image/png" in o.get("data", {})]
    assert len(images) >= 2, "the notebook's plots were not drawn"


def test_there_is_a_notebook():
    assert NOTEBOOKS, f"no notebook in {SOURCE / 'examples' / 'notebooks'}"
