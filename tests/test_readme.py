"""Every example in README.md runs: the python blocks, and the commands of the console blocks."""

import doctest
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

README = (Path(__file__).parents[1] / "README.md").read_text()
PYTHON_BLOCKS = re.findall(r"```python\n(.*?)```", README, re.S)
PYCON_BLOCKS = re.findall(r"```pycon\n(.*?)```", README, re.S)
COMMANDS = [
    line.split("#")[0].strip()
    for block in re.findall(r"```console\n(.*?)```", README, re.S)
    for line in block.splitlines()
    if line.startswith("python -m")
]


def test_python_examples_are_sessions_that_show_their_output():
    # A ```python block would only be run, not checked: the README uses ```pycon.
    assert not PYTHON_BLOCKS


@pytest.mark.parametrize("session", PYCON_BLOCKS, ids=lambda code: code.splitlines()[0][4:44])
def test_pycon_example_prints_what_the_readme_says(session):
    flags = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE
    test = doctest.DocTestParser().get_doctest(session, {}, "README.md", "README.md", 0)
    runner = doctest.DocTestRunner(optionflags=flags)
    runner.run(test)
    assert runner.failures == 0, f"{runner.failures} README example(s) printed otherwise"


@pytest.mark.parametrize("command", COMMANDS)
def test_command_example_runs(command, tmp_path):
    args = shlex.split(command)
    (tmp_path / "out").mkdir()
    subprocess.run([sys.executable, *args[1:]], cwd=tmp_path, check=True, capture_output=True,
                   timeout=600)


def test_readme_opens_with_the_two_commands():
    head = README[:1200]
    assert "make paper" in head and "make test" in head
