"""The teaching notebooks run from top to bottom in a fresh kernel (nbclient), and
say what they show: a cell that raises fails the test."""

from pathlib import Path

import nbformat
import pytest
from nbclient import NotebookClient

NOTEBOOKS = sorted((Path(__file__).resolve().parents[1] / "docs" / "notebooks").glob("*.ipynb"))


def test_there_is_a_first_lesson():
    assert [path.name for path in NOTEBOOKS] == ["first-lesson.ipynb"]


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_each_notebook_runs_and_draws(path, tmp_path):
    notebook = nbformat.read(path, as_version=4)
    NotebookClient(notebook, timeout=600, kernel_name="python3",
                   resources={"metadata": {"path": str(tmp_path)}}).execute()
    outputs = [output for cell in notebook.cells if cell.cell_type == "code"
               for output in cell.outputs]
    figures = [output for output in outputs if "image/png" in output.get("data", {})]
    assert len(figures) >= 4  # a figure for each of the lesson's curves and the flight
    text = "".join(output.get("text", "") for output in outputs)
    assert "natural frequency f_n0 = 1485.6 Hz" in text
    assert "1/2 superharmonic" in text and "primary" in text
    assert not [output for output in outputs if output.output_type == "error"]
