"""The notebooks under examples/ run from top to bottom (their own cells
assert the physics: RDSR β ≈ 1/4, α ≈ 1/2; Sq equal to SurfaceTopography's)."""

from pathlib import Path

import nbformat
import pytest
from nbclient import NotebookClient

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


@pytest.mark.parametrize("name", ["growth_exponents.ipynb", "roughness_analysis.ipynb"])
def test_notebook_runs(name, tmp):
    nb = nbformat.read(EXAMPLES / name, as_version=4)
    NotebookClient(nb, timeout=600, kernel_name="python3",
                   resources={"metadata": {"path": str(tmp)}}).execute()
    errors = [o for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", [])
              if o.get("output_type") == "error"]
    assert not errors
    assert any(p.suffix == ".png" for p in tmp.iterdir()), "the notebook drew its figure"
