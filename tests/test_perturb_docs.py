"""Every example of docs/perturb.md runs: the Python ones as doctests, the shell
commands in a temporary directory, with the output lines shown in the docs
(``...`` in a shown line stands for any text, as in a doctest)."""

import doctest
import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "perturb.md"
CONSOLE = re.compile(r"```console\n(.*?)```", re.DOTALL)
PYTHON = re.compile(r"```python\n(.*?)```", re.DOTALL)


def test_python_examples():
    """The Python blocks run in order, sharing one namespace, as doctests."""
    blocks = PYTHON.findall(DOC.read_text())
    test = doctest.DocTestParser().get_doctest("\n".join(blocks), {}, DOC.name, str(DOC), 0)
    assert len(test.examples) >= 8
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
    runner.run(test)
    assert runner.summarize(verbose=False).failed == 0


def console_examples():
    for block in CONSOLE.findall(DOC.read_text()):
        lines = block.strip().splitlines()
        assert lines[0].startswith("$ python -m perturb")
        yield lines[0][2:], lines[1:]


@pytest.mark.parametrize("command, shown", list(console_examples()))
def test_console_examples(command, shown, tmp_path):
    args = shlex.split(command)
    args[0] = sys.executable
    env = {**os.environ, "PYTHONPATH": str(ROOT)}  # this tree's code, whatever is installed
    done = subprocess.run(args, cwd=tmp_path, capture_output=True, text=True, check=False,
                          env=env)
    assert done.returncode == 0, done.stderr
    printed = done.stdout.splitlines()
    for line in shown:
        pattern = ".*".join(re.escape(part) for part in line.split("..."))
        assert any(re.fullmatch(pattern, row) for row in printed), line
    for name in re.findall(r"--(?:json|latex) (\S+)", command):
        assert (tmp_path / name).stat().st_size > 0
