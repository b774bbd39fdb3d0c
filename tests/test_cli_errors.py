"""What a command says when it cannot do what it was asked: one line, never a traceback.

Exit status 2 for bad input (before any work), 1 for a failure while working; an
unexpected error writes its traceback to a log file and names it.
"""

import errno
import subprocess
import sys
import time
from pathlib import Path

import pytest

from common import PLOT_FORMATS
from numerics import cli


def run(*args: str, **kwargs) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", *args], capture_output=True, text=True,
                          **kwargs)


def test_the_plot_formats_are_matplotlibs():
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    assert set(PLOT_FORMATS) == set(FigureCanvasAgg.get_supported_filetypes())


def test_an_unsupported_plot_format_is_refused_before_the_work(tmp_path):
    start = time.perf_counter()
    # 2,000 points at 0.3 Q would take tens of seconds: refused before any of it.
    out = run("numerics", "sweep", "--pa-frac", "0.3", "--fmin", "300", "--fmax", "3000",
              "--points", "2000", "--plot", str(tmp_path / "fig.xyz"), "--quiet")
    assert out.returncode == 2 and "Traceback" not in out.stderr
    assert "cannot draw a figure as .xyz; the formats are avif, eps, gif" in out.stderr
    assert time.perf_counter() - start < 20 and not list(tmp_path.iterdir())


def test_a_full_disk_is_one_line_and_status_1(tmp_path, monkeypatch, capsys):
    def full_disk(self, *args, **kwargs):
        raise OSError(errno.ENOSPC, "No space left on device", str(self))

    monkeypatch.setattr(Path, "write_text", full_disk)
    code = cli.main(["sweep", "--pa-frac", "0.05", "--fmin", "1300", "--fmax", "1400",
                     "--points", "3", "--quiet", "--json", str(tmp_path / "run.json")])
    err = capsys.readouterr().err
    assert code == 1 and "No space left on device" in err and "Traceback" not in err
    assert not list(tmp_path.iterdir())  # no half-written file, no temporary one


def test_an_unexpected_error_goes_to_a_log_file(monkeypatch, capsys):
    from numerics.cli import _info

    def broken(args):
        raise RuntimeError("a bug")

    parser = cli.build_parser()
    args = parser.parse_args(["info"])
    monkeypatch.setattr(args, "run", broken)
    assert _info is not None
    from common import run_command

    assert run_command(args) == 1
    err = capsys.readouterr().err
    assert "internal error (RuntimeError('a bug'))" in err and "Traceback" not in err
    log = Path(err.rsplit("the traceback is in ", 1)[1].strip())
    assert "RuntimeError: a bug" in log.read_text() and "Traceback" in log.read_text()
    log.unlink()


def test_bad_input_found_while_working_is_status_2(monkeypatch, capsys):
    parser = cli.build_parser()
    args = parser.parse_args(["info"])

    def refuses(args):
        raise ValueError("`pa_frac` must be a finite number >= 0, got -1.")

    monkeypatch.setattr(args, "run", refuses)
    from common import run_command

    assert run_command(args) == 2
    assert "error: `pa_frac` must be" in capsys.readouterr().err


def test_a_scene_nested_too_deep_is_one_line(tmp_path):
    scene = tmp_path / "deep.toml"
    scene.write_text("a = " + "[" * 100_000 + "]" * 100_000 + "\n")
    out = run("numerics", "scene", str(scene), "--out", str(tmp_path / "out"))
    assert out.returncode == 2 and "Traceback" not in out.stderr
    assert "nests its tables or arrays too deep" in out.stderr


@pytest.mark.parametrize("argv", [["info", "--json", "/dev/stdout"]])
def test_a_stream_is_written_as_a_stream(argv):
    out = run("numerics", *argv)
    assert out.returncode == 0 and '"y0_m": 2.25185562534611e-07' in out.stdout
    assert Path("/dev/stdout").is_symlink() or not Path("/dev/stdout").exists()
