"""The examples of README.md and docs/*.md run as tests, through sybil.

- ```pycon blocks are doctest sessions: each prints what the text shows (``...``
  stands for any text); the blocks of one file share a namespace, in order.
- ```console blocks are commands (``python -m ...``, optionally after ``$ ``);
  each runs in a new process, in a fresh folder that has an ``out/`` folder (and
  ``paper_checks/``, linked, for the scene files), and
  every line shown under it must match a printed line (``...``: any text). A
  file named by ``--json``, ``--latex``, ``--plot`` or ``--out`` must be written.
"""

from __future__ import annotations

import doctest
import os
import re
import shlex
import subprocess
import sys
import tempfile
from pathlib import Path

from sybil import Sybil
from sybil.evaluators.doctest import DocTestEvaluator
from sybil.evaluators.python import PythonEvaluator
from sybil.parsers.abstract.codeblock import PythonDocTestOrCodeBlockParser
from sybil.parsers.abstract.doctest import DocTestStringParser
from sybil.parsers.markdown import CodeBlockParser

ROOT = Path(__file__).resolve().parent
FLAGS = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE
OUTPUT_OPTIONS = ("--json", "--latex", "--plot", "--out")


class PyconParser(PythonDocTestOrCodeBlockParser):
    """```pycon blocks as doctest sessions."""

    codeblock_parser_class = CodeBlockParser

    def __init__(self) -> None:
        self.doctest_parser = DocTestStringParser(DocTestEvaluator(FLAGS))
        self.codeblock_parser = CodeBlockParser("pycon", PythonEvaluator())


def _commands(block: str) -> list[tuple[str, list[str]]]:
    """(command, lines shown under it) for each command of a console block."""
    found: list[tuple[str, list[str]]] = []
    for line in block.strip().splitlines():
        text = line.removeprefix("$ ")
        if text.startswith("python -m"):
            found.append((text.split(" #")[0].strip(), []))
        elif found and line.strip():
            found[-1][1].append(line)
    return found


def run_console(example) -> None:
    """Run each command of a console block; check what it shows and writes."""
    for command, shown in _commands(example.parsed):
        with tempfile.TemporaryDirectory() as folder:
            (Path(folder) / "out").mkdir()
            # The scene files, where a command run from the repository finds them.
            (Path(folder) / "paper_checks").symlink_to(ROOT / "paper_checks")
            args = shlex.split(command)
            env = {**os.environ, "PYTHONPATH": str(ROOT)}  # this tree's code
            done = subprocess.run([sys.executable, *args[1:]], cwd=folder, capture_output=True,
                                  text=True, timeout=900, env=env)
            assert done.returncode == 0, f"{command}\n{done.stderr}"
            printed = done.stdout.splitlines()
            for line in shown:
                pattern = ".*".join(re.escape(part) for part in line.split("..."))
                assert any(re.fullmatch(pattern, row.rstrip()) for row in printed), (
                    f"{command}: no printed line matches {line!r}")
            for option in OUTPUT_OPTIONS:
                if option in args:
                    target = Path(folder) / args[args.index(option) + 1]
                    assert target.exists(), f"{command}: {option} wrote nothing"


pytest_collect_file = Sybil(
    parsers=[PyconParser(), CodeBlockParser("console", run_console)],
    patterns=["README.md", "docs/*.md"],
    path=str(ROOT),
).pytest()
