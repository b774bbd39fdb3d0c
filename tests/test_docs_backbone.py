"""Every example in docs/backbone.md runs, and prints what its `# -> ` comments say."""

import contextlib
import doctest
import io
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

DOC = (Path(__file__).parents[1] / "docs" / "backbone.md").read_text()
PYTHON_BLOCKS = re.findall(r"```python\n(.*?)```", DOC, re.S)
COMMANDS = [
    # The full comparison takes about 10 s: kept out of the default run.
    pytest.param(line.strip(), marks=pytest.mark.slow) if " compare " in line else line.strip()
    for block in re.findall(r"```console\n(.*?)```", DOC, re.S)
    for line in block.splitlines()
    if line.startswith("python -m")
]


def expected_lines(code: str) -> list[str]:
    return [line.split("# -> ", 1)[1] for line in code.splitlines() if "# -> " in line]


def test_examples_run_and_print_what_they_say(tmp_path, monkeypatch):
    # The blocks share one namespace, as a reader runs them one after the other.
    monkeypatch.chdir(tmp_path)
    namespace: dict = {}
    checker = doctest.OutputChecker()
    for code in PYTHON_BLOCKS:
        out = io.StringIO()
        with contextlib.redirect_stdout(out):
            exec(compile(code, "docs/backbone.md", "exec"), namespace)
        got = out.getvalue().splitlines()
        want = expected_lines(code)
        assert len(got) == len(want), (got, want)
        for g, w in zip(got, want):
            assert checker.check_output(w + "\n", g + "\n", doctest.ELLIPSIS), (g, w)
    assert {"backbone.png", "fig4.png", "fig5.png"} <= {p.name for p in tmp_path.iterdir()}


@pytest.mark.parametrize("command", COMMANDS)
def test_command_example_runs(command, tmp_path):
    (tmp_path / "out").mkdir()
    args = shlex.split(command)
    subprocess.run([sys.executable, *args[1:]], cwd=tmp_path, check=True, capture_output=True,
                   timeout=600)
    for option in ("--json", "--plot"):
        if option in args:
            assert (tmp_path / args[args.index(option) + 1]).stat().st_size > 0, option
