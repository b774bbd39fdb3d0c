"""The docs site: its generated pages say what the code says, every page is in the
navigation, and the README is a short front door into it. (``make docs`` builds the
site with every warning an error; CI runs it.)"""

import importlib.util
import inspect
import re
import subprocess
import sys
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
README = (ROOT / "README.md").read_text(encoding="utf-8")


def _hooks():
    spec = importlib.util.spec_from_file_location("docs_hooks", DOCS / "hooks.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


HOOKS = _hooks()


def _nav_pages(nav) -> list[str]:
    pages = []
    for entry in nav:
        value = next(iter(entry.values())) if isinstance(entry, dict) else entry
        pages += _nav_pages(value) if isinstance(value, list) else [value]
    return pages


def test_every_page_is_in_the_navigation_once():
    import yaml  # MkDocs' own reader of its config; PyYAML comes with it

    config = yaml.safe_load((ROOT / "mkdocs.yml").read_text(encoding="utf-8"))
    pages = _nav_pages(config["nav"])
    notebooks = [f"notebooks/{p.name}" for p in (DOCS / "notebooks").glob("*.ipynb")]
    assert sorted(pages) == sorted([p.name for p in DOCS.glob("*.md")] + notebooks), pages
    assert len(pages) == len(set(pages))


def test_each_generated_page_holds_its_mark():
    for page, mark in (("api.md", "<!-- api -->"), ("cli.md", "<!-- cli-help -->"),
                       ("glossary.md", "<!-- glossary -->"),
                       ("gallery.md", "<!-- gallery -->"), ("benchmarks.md", "<!-- bench -->")):
        assert mark in (DOCS / page).read_text(encoding="utf-8"), page
    assert len(HOOKS.MARKS) == 5


def test_the_glossary_page_is_the_codes_glossary():
    from perturb.common import glossary_table

    page = HOOKS.on_page_markdown((DOCS / "glossary.md").read_text(encoding="utf-8"))
    assert glossary_table() in page and "<!--" not in page


def test_the_api_reference_lists_every_exported_class_and_function():
    import numerics
    import perturb

    reference = HOOKS.api_reference()
    for package in (perturb, numerics):
        for name in package.__all__:
            value = getattr(package, name)
            if inspect.isclass(value) or inspect.isfunction(value):
                assert f"::: {value.__module__}.{value.__qualname__}\n" in reference, name
            else:
                assert f"`{name}`" in reference, name
    assert "::: numerics.steady.options.SteadyOptions" in reference


def test_the_command_line_page_holds_every_commands_help():
    text = HOOKS.cli_help()
    for command in ("python -m perturb", "python -m numerics", "python -m paper_checks"):
        assert f"### `{command}`" in text
    for sub in ("info", "backbone", "sweep", "attractors", "compare", "scene", "continue",
                "atlas", "folds"):
        assert f"### `python -m numerics {sub}`" in text, sub
    assert "usage: python -m numerics sweep" in text and "issue" not in text.lower()


def test_the_gallery_shows_every_example_with_its_figures():
    text = HOOKS.gallery()
    examples = sorted((ROOT / "numerics" / "scenes" / "examples").glob("*.toml"))
    assert len(examples) == 9
    for path in examples:
        scene = tomllib.loads(path.read_text(encoding="utf-8"))
        assert f"## {scene['title']}" in text, path.stem
        assert f"python -m numerics scene {path.stem} --out out" in text
    figures = re.findall(r"\]\((figures/examples/[^)]+)\)", text)
    assert len(figures) >= len(examples)
    assert all((DOCS / figure).is_file() for figure in figures), figures


def test_the_readme_is_a_short_front_door_into_the_docs():
    assert len(README.splitlines()) <= 150
    assert "make paper" in README[:1200] and "make test" in README[:1200]
    for target in re.findall(r"\]\((docs/[^)#]+)", README):
        assert (ROOT / target).exists(), target
    assert "issue" not in README.lower()


def test_no_page_speaks_of_issues_or_sessions():
    for path in [*DOCS.glob("*.md"), ROOT / "README.md"]:
        text = path.read_text(encoding="utf-8").lower()
        assert not re.search(r"\bissue \d+|\bsession\b", text), path.name


def _scene(*args, cwd):
    return subprocess.run([sys.executable, "-m", "numerics", "scene", *args], cwd=cwd,
                          capture_output=True, text=True, timeout=600)


def test_bundled_scenes_are_listed_and_run_by_name_from_any_folder(tmp_path):
    listed = _scene("--list", cwd=tmp_path)
    assert listed.returncode == 0, listed.stderr
    names = [line.split()[0] for line in listed.stdout.splitlines()]
    assert len(names) == 17 and "linear-contact" in names and "fig2-fig3" in names
    done = _scene("linear-contact", "--quiet", "--out", "here", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("SceneRun: 'Linear contact") and (tmp_path / "here").is_dir()
    # The docs' path to it finds the installed file too, outside the repository.
    done = _scene("numerics/scenes/examples/linear-contact.toml", "--quiet", "--out",
                  "there", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    missing = _scene("no-such-scene", cwd=tmp_path)
    assert missing.returncode == 2 and "--list" in missing.stderr


def test_the_benchmark_page_is_drawn_from_a_runs_record(tmp_path):
    import json

    record = {"date": "2026-01-01", "processors": 2, "machine": "x86_64", "python": "3.11",
              "versions": {"numpy": "2.0"}, "sections": [{"section": "kernel", "rows": [
                  {"figure": "lane-steps/s", "value": 3.5e8, "baseline": 8e6, "unit": "",
                   "ratio": 43.75},
                  {"figure": "compile [s]", "value": 12.0, "baseline": None, "unit": "s",
                   "ratio": None}]}]}
    (tmp_path / "bench.json").write_text(json.dumps(record))
    page = HOOKS.benchmarks(tmp_path / "bench.json")
    assert "| lane-steps/s | 3.5e+08 | 8e+06 | 43.75× |" in page
    assert "| compile [s] | 12 s |  |  |" in page and "2 processors" in page
    assert "make bench" in HOOKS.benchmarks(tmp_path / "none.json")


def test_the_citation_file_reads_and_names_the_paper():
    import yaml

    citation = yaml.safe_load((ROOT / "CITATION.cff").read_text(encoding="utf-8"))
    assert citation["cff-version"] == "1.2.0" and citation["license"] == "BSD-3-Clause"
    titles = [reference["title"] for reference in citation["references"]]
    assert any("Part 1" in title for title in titles)


def test_the_console_scripts_run_each_command():
    from importlib import metadata

    version = metadata.version("contact-resonances")
    for script in ("contact-numerics", "contact-perturb", "contact-paper-checks"):
        path = Path(sys.executable).parent / script
        done = subprocess.run([str(path), "--version"], capture_output=True, text=True)
        assert done.returncode == 0, (script, done.stderr)
        assert done.stdout == f"{script} {version}\n"
        usage = subprocess.run([str(path), "--help"], capture_output=True, text=True).stdout
        assert usage.startswith(f"usage: {script} "), usage
