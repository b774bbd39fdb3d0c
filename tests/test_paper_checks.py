"""`python -m paper_checks --quick`: the report the test suite can afford."""

import json
import subprocess
import sys


def test_paper_checks_quick_writes_the_report(tmp_path):
    done = subprocess.run(
        [sys.executable, "-m", "paper_checks", "--quick", "--out", str(tmp_path)],
        capture_output=True, text=True)
    report = json.loads((tmp_path / "report.json").read_text())
    assert len(report["claims"]) == 11 and all(
        {"id", "statement", "passed", "measured"} <= set(c) for c in report["claims"])
    failed = [c["id"] for c in report["claims"] if not c["passed"]]
    assert not failed and done.returncode == 0, (failed, done.stdout)
    text = (tmp_path / "report.md").read_text()
    for figure in report["figures"].values():
        assert (tmp_path / figure).stat().st_size > 10_000 and f"]({figure})" in text


def test_an_unusable_output_folder_is_refused_before_any_work(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("")
    done = subprocess.run([sys.executable, "-m", "paper_checks", "--quick", "--out",
                           str(blocker)], capture_output=True, text=True, timeout=60)
    assert done.returncode == 2 and "argument --out" in done.stderr
