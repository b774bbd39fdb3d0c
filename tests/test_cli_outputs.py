"""Every option that writes a file is checked before any work (issue 9, item 5).

A folder where a file is wanted, a missing parent folder and an unwritable place
each exit with status 2 and one line naming the option, in well under 2 s: the
check is argparse's, so nothing is computed first.
"""

import time

import pytest

from numerics.cli import main as numerics_main
from paper_checks.__main__ import main as paper_main
from perturb.__main__ import main as perturb_main

#: (entry point, the arguments before the output option, the output option)
FILE_OPTIONS = [
    (numerics_main, ["info"], "--json"),
    (numerics_main, ["backbone"], "--json"),
    (numerics_main, ["sweep"], "--json"),
    (numerics_main, ["sweep"], "--plot"),
    (numerics_main, ["attractors", "--fe", "740", "--pa-frac", "0.15"], "--json"),
    (numerics_main, ["compare"], "--json"),
    (numerics_main, ["compare"], "--plot"),
    (numerics_main, ["continue", "--pa-frac", "0.05"], "--json"),
    (numerics_main, ["continue", "--fe", "1400", "--pa-min", "0.02", "--pa-max", "0.1"],
     "--json"),
    (numerics_main, ["continue", "--fe", "1400", "--pa-min", "0.02", "--pa-max", "0.1"],
     "--plot"),
    (perturb_main, ["derive", "--order", "2"], "--json"),
    (perturb_main, ["derive", "--order", "2"], "--latex"),
    (perturb_main, ["backbone", "--order", "2"], "--json"),
    (perturb_main, ["response", "--pa-frac", "0.05"], "--json"),
]
#: Places no file can be written, even by root: /proc takes no new files.
BAD_FILES = {"a folder": "{tmp}", "a missing parent": "{tmp}/missing/x.json",
             "an unwritable place": "/proc/x.json"}


def _exits_naming(main, argv, option, capsys):
    start = time.perf_counter()
    with pytest.raises(SystemExit) as exit_:
        main(argv)
    elapsed = time.perf_counter() - start
    err = capsys.readouterr().err.strip().splitlines()
    assert exit_.value.code == 2
    assert f"argument {option}" in err[-1], err
    assert elapsed < 2.0, f"{elapsed:.2f} s: the check came after some work"


@pytest.mark.parametrize("what", sorted(BAD_FILES))
@pytest.mark.parametrize("main, before, option", FILE_OPTIONS,
                         ids=[f"{m.__module__.split('.')[0]} {b[0]} {o}"
                              for m, b, o in FILE_OPTIONS])
def test_an_unusable_output_file_exits_2_before_any_work(main, before, option, what, tmp_path,
                                                         capsys):
    path = BAD_FILES[what].format(tmp=tmp_path)
    _exits_naming(main, [*before, option, path], option, capsys)


@pytest.mark.parametrize("path", ["{tmp}/missing/out", "/proc/out", "{tmp}/file"])
def test_an_unusable_report_folder_exits_2_before_any_work(path, tmp_path, capsys):
    (tmp_path / "file").write_text("")
    _exits_naming(paper_main, ["--quick", "--out", path.format(tmp=tmp_path)], "--out", capsys)
