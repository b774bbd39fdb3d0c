"""What every command line does alike: --version, --json - and progress only on a terminal."""

import json
import os
import subprocess
import sys
from importlib import metadata

import pytest

COMMANDS = [["numerics"], ["numerics", "sweep"], ["numerics", "continue"], ["perturb"],
            ["perturb", "derive"], ["paper_checks"]]


def _run(*args, env=None):
    return subprocess.run([sys.executable, "-m", *args], capture_output=True, text=True,
                          env=None if env is None else os.environ | env)


@pytest.mark.parametrize("command", COMMANDS, ids=" ".join)
def test_every_command_says_its_version(command):
    done = _run(*command, "--version")
    assert done.returncode == 0, done.stderr
    version = metadata.version("contact-resonances")
    assert done.stdout == f"python -m {' '.join(command)} {version}\n"


def test_every_package_has_the_distributions_version():
    import numerics
    import paper_checks
    import perturb

    version = metadata.version("contact-resonances")
    assert numerics.__version__ == perturb.__version__ == paper_checks.__version__ == version


def test_json_to_stdout_is_the_json_alone_and_the_file_the_same(tmp_path):
    # `--json -`: stdout holds the JSON document alone (the table goes to stderr), the
    # same document that `--json FILE` writes.
    to_stdout = _run("numerics", "info", "--json", "-")
    assert to_stdout.returncode == 0, to_stdout.stderr
    assert "static contact deflection" in to_stdout.stderr
    _run("numerics", "info", "--json", str(tmp_path / "info.json"))
    written = json.loads((tmp_path / "info.json").read_text())
    shown = json.loads(to_stdout.stdout)
    assert shown.pop("provenance")["version"] == written.pop("provenance")["version"]
    assert shown == written  # the same numbers; the provenance says when each was written
    assert not (tmp_path / "-").exists() and not os.path.exists("-")


def test_a_result_written_to_stdout_loads_back():
    from numerics import load

    done = _run("numerics", "sweep", "--pa-frac", "0.05", "--fmin", "700", "--fmax", "800",
                "--points", "3", "--quiet", "--json", "-")
    assert done.returncode == 0, done.stderr
    data = json.loads(done.stdout)
    assert data["kind"] == "Sweep" and "sweep" in done.stderr.lower()
    import tempfile
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "sweep.json")
        with open(path, "w", encoding="utf-8") as file:
            file.write(done.stdout)
        assert type(load(path)).__name__ == "Sweep"


def test_json_to_stdout_refuses_a_second_document():
    # With --series, continue writes the series' stability beside the file: on stdout
    # there is room for one document, so it is refused before any work.
    done = _run("numerics", "continue", "--pa-frac", "0.05", "--series", "2", "--json", "-")
    assert done.returncode == 2 and "argument --json" in done.stderr and done.stdout == ""


def test_progress_is_drawn_on_a_terminal_or_when_asked_for(monkeypatch):
    from perturb.common import progress
    from perturb.common._progress import PROGRESS_VARIABLE

    class Terminal:
        def __init__(self, tty):
            self.tty, self.text = tty, ""

        def isatty(self):
            return self.tty

        def write(self, text):
            self.text += text

        def flush(self):
            pass

    monkeypatch.delenv(PROGRESS_VARIABLE, raising=False)
    for tty, asked, quiet, drawn in [(True, None, False, True), (False, None, False, False),
                                     (False, "always", False, True),
                                     (True, None, True, False), (False, "always", True, False)]:
        stream = Terminal(tty)
        monkeypatch.setattr(sys, "stderr", stream)
        if asked:
            monkeypatch.setenv(PROGRESS_VARIABLE, asked)
        else:
            monkeypatch.delenv(PROGRESS_VARIABLE, raising=False)
        bar = progress(3, "work", quiet=quiet)
        bar.update(3)
        bar.close()
        assert ("work" in stream.text) == drawn, (tty, asked, quiet)


def _commands():
    """(name, parser, examples) of every subcommand of the three command lines, and the
    top-level parsers with no examples."""
    import argparse

    import perturb.__main__ as perturb_main
    from numerics.cli import EXAMPLES, build_parser

    found = []
    for top, examples in ((build_parser(), EXAMPLES),
                          (perturb_main.build_parser(), perturb_main.EXAMPLES)):
        found.append((top.prog, top, None))
        for action in top._actions:
            if isinstance(action, argparse._SubParsersAction):
                found += [(command.prog, command, examples[name])
                          for name, command in action.choices.items()]
    return found


def test_every_help_page_renders_with_a_description_an_example_and_the_defaults():
    # A help string that formats its default with %(default)g once broke `continue
    # --help` (a traceback) where the default is None: every page is rendered here.
    import argparse
    import shlex

    for prog, parser, example in _commands():
        text = parser.format_help()
        assert parser.description and "issue" not in text.lower(), prog
        if example is None:
            continue
        assert f"example:\n  {example}" in text, prog
        words = shlex.split(example)[2:]  # after "python -m"
        top = [p for name, p, e in _commands() if e is None and name.split()[-1] == words[0]]
        top[0].parse_args(words[1:])  # the example is a valid command line
        for action in parser._actions:
            if not action.option_strings or action.help == argparse.SUPPRESS:
                continue
            assert action.help, (prog, action.option_strings)
            has_default = action.default not in (None, False, [], argparse.SUPPRESS)
            if has_default and not action.required:
                assert "default" in action.help, (prog, action.option_strings)
