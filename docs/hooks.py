"""The docs site's pages that are generated from the code, at every build (``make docs``).

MkDocs calls ``on_page_markdown`` for every page; a page that holds one of the marks
below gets, in its place, what the code says today:

- ``<!-- api -->``: the reference of every public name of ``perturb`` and ``numerics``,
  from their docstrings (mkdocstrings renders each ``:::`` line);
- ``<!-- cli-help -->``: the ``--help`` of every command and subcommand;
- ``<!-- glossary -->``: the glossary (``perturb.common.glossary_table``);
- ``<!-- gallery -->``: the example scenes, with their descriptions and figures;
- ``<!-- bench -->``: the figures of the last ``make bench``, each beside its baseline
  from the same run (docs/benchmarks.json, which ``make bench`` writes).

Nothing here imports MkDocs: the tests call the same functions (tests/test_docs.py).
"""

from __future__ import annotations

import argparse
import inspect
import json
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "numerics" / "scenes" / "examples"
FIGURES = ROOT / "docs" / "figures" / "examples"
BENCH = ROOT / "docs" / "benchmarks.json"
#: The help texts are rendered this wide, whatever the terminal of the build.
HELP_WIDTH = 88


def api_reference() -> str:
    """A ``:::`` line for each class and function that ``perturb`` and ``numerics`` export,
    at the module that defines it (their ``__all__`` is resolved lazily, so the
    names are looked up by importing them); each package's constants are listed."""
    import numerics
    import perturb

    parts = []
    for package in (perturb, numerics):
        parts.append(f"## `{package.__name__}`\n")
        values = []
        for name in package.__all__:
            value = getattr(package, name)
            if inspect.isclass(value) or inspect.isfunction(value):
                parts.append(f"::: {value.__module__}.{value.__qualname__}\n")
            else:
                values.append(f"`{name}`")
        if values:
            parts.append(f"Also exported: {', '.join(values)}.\n")
    return "\n".join(parts)


def _parsers() -> list[tuple[str, argparse.ArgumentParser]]:
    from numerics.cli import build_parser as numerics_parser
    from paper_checks.__main__ import build_parser as paper_parser
    from perturb.__main__ import build_parser as perturb_parser

    found = []
    for parser in (perturb_parser(), numerics_parser(), paper_parser()):
        found.append((parser.prog, parser))
        for action in parser._actions:  # argparse keeps subcommands here alone
            if isinstance(action, argparse._SubParsersAction):
                found += [(sub.prog, sub) for sub in action.choices.values()]
    return found


def cli_help() -> str:
    """Every command's ``--help``, as it prints it."""
    import os

    width = os.environ.get("COLUMNS")
    os.environ["COLUMNS"] = str(HELP_WIDTH)
    try:
        return "\n".join(f"### `{prog}`\n\n```text\n{parser.format_help().rstrip()}\n```\n"
                         for prog, parser in _parsers())
    finally:
        if width is None:
            del os.environ["COLUMNS"]
        else:
            os.environ["COLUMNS"] = width


def glossary() -> str:
    from perturb.common import glossary_table

    return glossary_table()


def gallery() -> str:
    """Each example scene: its title, what it shows, the command that runs it and the
    figures it writes (drawn by ``make figures``, in docs/figures/examples)."""
    parts = []
    for path in sorted(EXAMPLES.glob("*.toml")):
        scene = tomllib.loads(path.read_text(encoding="utf-8"))
        output = scene.get("output", {})
        files = list(output.get("figures", {}).values())
        if "animation" in output:
            files.append(f"{path.stem}-slider.gif")
        shown = [name for name in files if (FIGURES / name).exists()]
        description = " ".join(scene.get("description", "").split())
        parts.append(f"## {scene['title']}\n\n{description}\n\n```console\n"
                     f"python -m numerics scene {path.stem} --out out\n```\n")
        parts += [f"![{scene['title']}](figures/examples/{name})\n" for name in shown]
    return "\n".join(parts)


def benchmarks(path: Path = BENCH) -> str:
    """The tables of a ``make bench`` run: per benchmark, each figure, its baseline from
    the same run, and the ratio (above 1: better than the baseline)."""
    if not path.is_file():
        return "No run is recorded here: `make bench` writes it (docs/benchmarks.json).\n"
    run = json.loads(path.read_text(encoding="utf-8"))
    versions = ", ".join(f"{name} {version}" for name, version in run["versions"].items())
    parts = [f"Measured on {run['date']}, {run['processors']} processors ({run['machine']}), "
             f"Python {run['python']}, {versions}.\n"]
    for section in run["sections"]:
        if not section["rows"]:
            continue
        parts.append(f"## {section['section']}\n\n| figure | value | baseline | ratio |\n"
                     "|---|---|---|---|")
        for r in section["rows"]:
            unit = f" {r['unit']}" if r["unit"] else ""
            base = "" if r["baseline"] is None else f"{r['baseline']:.4g}{unit}"
            ratio = "" if r["ratio"] is None else f"{r['ratio']:.2f}×"
            figure = r["figure"].strip().replace("|", "\\|")
            parts.append(f"| {figure} | {r['value']:.4g}{unit} | {base} | {ratio} |")
        parts.append("")
    return "\n".join(parts)


MARKS = {"<!-- api -->": api_reference, "<!-- cli-help -->": cli_help,
         "<!-- glossary -->": glossary, "<!-- gallery -->": gallery,
         "<!-- bench -->": benchmarks}


def on_page_markdown(markdown: str, **_) -> str:
    for mark, render in MARKS.items():
        if mark in markdown:
            markdown = markdown.replace(mark, render())
    return markdown
