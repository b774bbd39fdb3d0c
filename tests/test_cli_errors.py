"""Bad command-line input is an argparse error (exit 2) naming the option, before any work."""

import pytest

from numerics.cli import main


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
        main(argv)
    assert exit_.value.code == 2
    assert message in capsys.readouterr().err
