"""What a command says when it cannot do what it was asked: one line, never a traceback.

Bad command-line input is an argparse error (exit 2) naming the option, before any
work; so is work past its bounds and input outside the tested ranges. A failure while
working is status 1; an unexpected error writes its traceback to a log file and names it.
"""

import errno
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from numerics import cli
from perturb.common import PLOT_FORMATS


def run(*args: str, **kwargs) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", *args], capture_output=True, text=True,
                          **kwargs)


@pytest.mark.parametrize(
    "argv, message",
    [
        (["sweep", "--fmin", "0"], "--fmin: must be a finite number > 0, got '0'"),
        (["sweep", "--pa-frac", "-0.1"], "--pa-frac: must be a finite number >= 0"),
        (["sweep", "--pa-frac", "nan"], "--pa-frac: must be finite, got 'nan'"),
        (["sweep", "--fmax", "inf"], "--fmax: must be finite, got 'inf'"),
        (["sweep", "--steps", "3"], "--steps: must be an integer >= 4, got '3'"),
        (["sweep", "--points", "1"], "--points: must be an integer >= 2, got '1'"),
        (["sweep", "--tol", "-1"], "--tol: must be a finite number > 0"),
        (["sweep", "--fmin", "900", "--fmax", "800"], "--fmax: must be above --fmin"),
        (["sweep", "--plot", "/proc/fig.png"], "argument --plot"),
        (["sweep", "--json", "/nonexistent/x.json"], "--json: folder '/nonexistent'"),
        (["attractors", "--fe", "0", "--pa-frac", "0.1"], "--fe: must be a finite number > 0"),
        (["attractors", "--fe", "500", "--pa-frac", "-1"], "--pa-frac: must be a finite"),
        (["info", "--json", "/nope/a.json"], "--json: folder '/nope' does not exist"),
    ],
)
def test_bad_input_names_the_option(argv, message, capsys):
    with pytest.raises(SystemExit) as exit_:
        cli.main(argv)
    assert exit_.value.code == 2
    assert message in capsys.readouterr().err


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
    def full_disk(self, text, *args, **kwargs):  # a part written, then the disk is full
        with open(self, "w") as file:
            file.write(text[:3])
        raise OSError(errno.ENOSPC, "No space left on device", str(self))

    monkeypatch.setattr(Path, "write_text", full_disk)
    code = cli.main(["sweep", "--pa-frac", "0.05", "--fmin", "1300", "--fmax", "1400",
                     "--points", "3", "--quiet", "--json", str(tmp_path / "run.json")])
    err = capsys.readouterr().err
    assert code == 1 and "No space left on device" in err and "Traceback" not in err
    assert f"{tmp_path / 'run.json'}" in err  # the file asked for, not the temporary one
    assert not list(tmp_path.iterdir())  # no half-written file, no temporary one


def test_an_unexpected_error_goes_to_a_log_file(monkeypatch, capsys):
    def broken(args):
        raise RuntimeError("a bug")

    parser = cli.build_parser()
    args = parser.parse_args(["info"])
    monkeypatch.setattr(args, "run", broken)
    from perturb.common import run_command

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
    from perturb.common import run_command

    assert run_command(args) == 2
    assert "error: `pa_frac` must be" in capsys.readouterr().err


def test_a_scene_nested_too_deep_is_one_line(tmp_path):
    scene = tmp_path / "deep.toml"
    scene.write_text("a = " + "[" * 100_000 + "]" * 100_000 + "\n")
    out = run("numerics", "scene", str(scene), "--out", str(tmp_path / "out"))
    assert out.returncode == 2 and "Traceback" not in out.stderr
    assert "nests its tables or arrays too deep" in out.stderr


def test_a_link_to_stdout_is_written_as_a_stream(tmp_path):
    # As /dev/stdout is: a link to the process's descriptor 1, here redirected to a
    # file. The link is written through, not replaced, and the summary printed after
    # the JSON follows it instead of overwriting its start.
    link = tmp_path / "stdout"
    link.symlink_to("/proc/self/fd/1")
    with open(tmp_path / "out.txt", "w") as out:
        done = subprocess.run([sys.executable, "-m", "numerics", "sweep", "--pa-frac", "0.05",
                               "--fmin", "1300", "--fmax", "1400", "--points", "3", "--quiet",
                               "--json", str(link)], stdout=out, stderr=subprocess.PIPE,
                              text=True)
    assert done.returncode == 0 and link.is_symlink()
    text = (tmp_path / "out.txt").read_text()
    assert text.startswith('{\n "kind": "Sweep"') and "\nSweep: 2 runs, 6 points" in text


def test_another_value_error_is_status_1_with_a_log(monkeypatch, capsys):
    from perturb.common import run_command

    args = cli.build_parser().parse_args(["info"])
    monkeypatch.setattr(args, "run", lambda args: np.add(np.ones(2), np.ones(3)))
    assert run_command(args) == 1
    err = capsys.readouterr().err
    assert "operands could not be broadcast" in err and "the traceback is in" in err
    Path(err.rsplit("the traceback is in ", 1)[1].strip().rstrip(")")).unlink()


def test_a_scene_never_writes_through_a_symlink_in_its_folder(tmp_path):
    from numerics.scenes import parse_scene, run_scene

    outside = tmp_path / "outside.png"
    outside.write_bytes(b"keep me")
    out = tmp_path / "out"
    out.mkdir()
    (out / "app.png").symlink_to(outside)
    scene = parse_scene('[excitation]\npa_frac = 0.05\nfrequency_hz = [800.0, 900.0]\n'
                        '[study]\nkind = "analytic_response"\n[output]\nfigures = ["app"]\n')
    assert run_scene(scene, out=out).files == ["app.png"]
    assert outside.read_bytes() == b"keep me"
    assert not (out / "app.png").is_symlink()
    assert (out / "app.png").read_bytes().startswith(b"\x89PNG")
    assert sorted(p.name for p in out.iterdir()) == ["app.png"]  # no temporary file left


def test_a_figure_that_fails_to_draw_leaves_nothing(tmp_path, monkeypatch):
    from numerics.plots import figure as figure_module

    def fails(figure, path):
        Path(path).write_bytes(b"half a")
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(figure_module, "_write_png", fails)
    import matplotlib.figure

    with pytest.raises(OSError, match="No space"):
        figure_module.finish(matplotlib.figure.Figure(), tmp_path / "fig.png")
    assert not list(tmp_path.iterdir())


def _children(pid: int) -> list[int]:
    """The live (not zombie) child processes of ``pid``, from /proc."""
    found = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            state, parent = stat.read_text().rsplit(")", 1)[1].split()[:2]
        except (OSError, ValueError):
            continue
        if int(parent) == pid and state != "Z":
            found.append(int(stat.parent.name))
    return found


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="/proc and prctl")
def test_a_killed_paper_checks_takes_its_workers_with_it(tmp_path):
    import os
    import signal

    run = subprocess.Popen([sys.executable, "-m", "paper_checks", "--quick", "--jobs", "2",
                            "--quiet", "--out", str(tmp_path / "out")],
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    workers: list[int] = []
    deadline = time.monotonic() + 30
    while len(workers) < 2 and time.monotonic() < deadline:
        time.sleep(0.1)
        workers = _children(run.pid)
    assert len(workers) >= 2, "the workers did not start"
    os.kill(run.pid, signal.SIGKILL)
    run.wait()
    deadline = time.monotonic() + 10
    while any(_alive(w) for w in workers) and time.monotonic() < deadline:
        time.sleep(0.1)
    left = [w for w in workers if _alive(w)]
    assert not left, f"workers {left} outlived the killed run"
    assert not (tmp_path / "out" / "report.md").exists()  # stopped before it: no report


def _alive(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"


@pytest.mark.parametrize("argv, limit", [
    (["perturb", "derive", "--order", "25"], 24),
    (["perturb", "derive", "--order", "7", "--set", "m2=1.5"], 6),
    (["perturb", "backbone", "--order", "101"], 100),
    (["perturb", "backbone", "--order", "51", "--set", "m2=1.5"], 50),
    (["perturb", "response", "--order", "25", "--pa-frac", "0.05", "--points", "3"], 24),
    (["numerics", "compare", "--orders", "4", "25"], 24),
])
def test_an_order_past_about_a_minute_is_refused_before_the_work(argv, limit):
    start = time.perf_counter()
    out = run(*argv)
    assert out.returncode == 2 and "Traceback" not in out.stderr
    assert f"is above {limit}, the largest that" in out.stderr and "--allow-slow" in out.stderr
    assert time.perf_counter() - start < 20


def test_allow_slow_goes_past_the_limit():
    from perturb import backbone_series, frequency_response

    with pytest.raises(ValueError, match="`order` 25 is above 24"):
        frequency_response([1000.0], 0.05, 25)
    with pytest.raises(ValueError, match="`order` 101 is above 100"):
        backbone_series(101, "paper")
    # The consistent series of the paper's contact by the scheme: quick at any order.
    response = frequency_response([1000.0, 1100.0], 0.05, 25, allow_slow=True)
    assert response.branches[0].valid.all()


@pytest.mark.parametrize("argv, message", [
    (["numerics", "atlas", "--grid", "319", "319", "--quiet"],
     "more than the limit of 2000000 (some 2 to 3 minutes"),
    (["numerics", "backbone", "--points", "1000000"], "must be an integer <= 100000"),
    (["numerics", "continue", "--pa-frac", "0.05", "--steps", "16777216"],
     "must be an integer <= 1048576"),
    (["numerics", "atlas", "--grid", "2", "2", "--workers", "100000", "--quiet"],
     "twice the"),
])
def test_work_past_its_bound_is_refused_at_once(argv, message):
    start = time.perf_counter()
    out = run(*argv)
    assert out.returncode == 2 and message in out.stderr and "Traceback" not in out.stderr
    assert time.perf_counter() - start < 20


def test_a_taylor_spring_of_absurd_degree_is_refused(tmp_path):
    scene = tmp_path / "taylor.toml"
    scene.write_text('effects = {spring = "taylor", taylor_degree = 1000}\n[excitation]\n'
                     'pa_frac = 0.05\nfrequency_hz = [1000.0]\n[study]\nkind = "sweep"\n')
    start = time.perf_counter()
    out = run("numerics", "scene", str(scene), "--out", str(tmp_path / "out"))
    assert out.returncode == 2 and "`taylor_degree` must be an integer <= 16" in out.stderr
    assert time.perf_counter() - start < 20


@pytest.mark.parametrize("argv, message", [
    (["numerics", "sweep", "--pa-frac", "0.1", "--fmin", "1e12", "--fmax", "2e12",
      "--points", "3"], "`f_e / f_n0` (the excitation frequency over the natural one) is"),
    (["numerics", "sweep", "--pa-frac", "7", "--points", "3"],
     "`pa_frac` (the force amplitude over the weight Q) is 7, outside 0 to 5"),
    (["numerics", "attractors", "--fe", "1000", "--pa-frac", "0.1", "--set", "M=1e300"],
     "`y0_m` (the static deflection [m]) is 4.907e+143, outside"),
    (["numerics", "attractors", "--fe", "1000", "--pa-frac", "0.1", "--set", "S=1e-300"],
     "outside"),
    (["numerics", "atlas", "--fmin", "1e11", "--fmax", "2e11", "--grid", "2", "2"],
     "`f_e / f_n0`"),
    (["numerics", "compare", "--orders", "2", "--pa-frac", "6"], "`pa_frac`"),
])
def test_inputs_outside_the_tested_ranges_are_refused(argv, message):
    out = run(*argv, "--quiet")
    assert out.returncode == 2 and message in out.stderr and "--unchecked" in out.stderr
    assert "Traceback" not in out.stderr


def test_unchecked_goes_past_the_ranges():
    from numerics import sweep

    with pytest.raises(ValueError, match="`pa_frac`"):
        sweep([1000.0], 6.0)
    past = sweep([1000.0], 6.0, direction="up", unchecked=True)
    assert past.runs[0].status.size == 1


def test_a_scene_past_the_ranges_is_refused_unless_unchecked(tmp_path):
    from numerics.scenes import parse_scene, run_scene

    text = ('[excitation]\npa_frac = 6.0\nfrequency_hz = [1000.0]\n'
            '[study]\nkind = "sweep"\ndirection = "up"\n')
    with pytest.raises(ValueError, match="a scene's unchecked = true"):
        run_scene(parse_scene(text))
    run = run_scene(parse_scene("unchecked = true\n" + text))
    assert run.outcomes[0].runs[0].status.size == 1


@pytest.mark.parametrize("error, code, said", [
    (OSError(errno.ENOSPC, "No space left on device", "out/report.json"), 1,
     "error: No space left on device: 'out/report.json'"),
    (RuntimeError("a fault of its own"), 1, "internal error (RuntimeError('a fault of its own'))"),
    # A ValueError deep in the checks names no option of the user's: internal, logged.
    (ValueError("`order` must be >= 0, got -1."), 1, "internal error (RuntimeError("),
])
def test_paper_checks_says_a_failure_in_one_line(tmp_path, monkeypatch, capsys, error, code,
                                                 said):
    import paper_checks.report
    from paper_checks.__main__ import main

    def fail(*args, **kwargs):
        raise error

    monkeypatch.setattr(paper_checks.report, "write_report", fail)
    assert main(["--quick", "--out", str(tmp_path / "out")]) == code
    err = capsys.readouterr().err
    assert said in err and "Traceback" not in err and len(err.strip().splitlines()) == 1
    if "internal error" in err:  # the log it names holds the traceback
        log = Path(err.rsplit("the traceback is in ", 1)[1].strip())
        assert "Traceback" in log.read_text()
        log.unlink()
