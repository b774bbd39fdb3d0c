"""The teaching notebooks run from top to bottom in a fresh kernel (nbclient), their
sliders included, and each slider's callback is called once more with other values,
as a move of the slider would."""

from pathlib import Path

import nbformat
import pytest
from nbclient import NotebookClient

FOLDER = Path(__file__).resolve().parents[1] / "docs" / "notebooks"
#: Each lesson, what its slider calls on a move, and how many figures the cells draw
#: (the slider's own figure is drawn into its widget, not into the cell's outputs).
LESSONS = {
    "1-linear-and-nonlinear": ("compare_contacts(0.1)", 3),
    "2-superharmonics": ("spectrum(1000.0, 0.05)", 3),
    "3-jumps-folds-continuation": ("jumps_and_folds(0.03)", 3),
    "4-series": ("series_and_simulator(2, 0.03)", 2),
}


def test_the_four_lessons_are_there_and_written_by_their_script():
    assert sorted(path.stem for path in FOLDER.glob("*.ipynb")) == sorted(LESSONS)
    import importlib.util

    spec = importlib.util.spec_from_file_location("make_notebooks",
                                                  FOLDER / "make_notebooks.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    for name, cells in module.LESSONS.items():  # the notebooks are what the script writes
        written = nbformat.read(FOLDER / f"{name}.ipynb", as_version=4)
        assert [cell.source for cell in written.cells] == [text.strip() for _, text in cells]


@pytest.mark.parametrize("name", sorted(LESSONS))
def test_each_lesson_runs_its_slider_and_draws(name, tmp_path):
    notebook = nbformat.read(FOLDER / f"{name}.ipynb", as_version=4)
    callback, least = LESSONS[name]
    notebook.cells.append(nbformat.v4.new_code_cell(callback))
    NotebookClient(notebook, timeout=600, kernel_name="python3",
                   resources={"metadata": {"path": str(tmp_path)}}).execute()
    outputs = [output for cell in notebook.cells if cell.cell_type == "code"
               for output in cell.outputs]
    assert not [output for output in outputs if output.output_type == "error"]
    figures = [output for output in outputs if "image/png" in output.get("data", {})]
    assert len(figures) == least, len(figures)
    widgets = [output for output in outputs
               if "application/vnd.jupyter.widget-view+json" in output.get("data", {})]
    assert widgets, "the slider was not drawn"
    last = notebook.cells[-1].outputs
    assert any("image/png" in output.get("data", {}) for output in last)  # the move drew
    text = "".join(output.get("text", "") for output in outputs)
    assert "natural frequency f_n0 = 1485.6 Hz" in text
