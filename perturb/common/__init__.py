"""What the three packages share: one vocabulary, one result contract, one set of checks.

- ``Status``: the one status of a lane (``_status.py``);
- ``Result``, ``result``, ``load``: the contract of every result object
  (``_results.py``), written by the one JSON writer (``_json.py``);
- the input checks of every public function (``_checks.py``) and the argument
  types of every command line (``_cli.py``);
- progress on stderr (``_progress.py``, through tqdm), and the processors to use
  (``_processors.py``);
- a package's names imported at first use (``_lazy.py``);
- ``GLOSSARY``: one name per quantity (``_glossary.py``, the docs site's glossary page).

It imports neither sympy nor numba, so the command lines can start without them.
"""

from ._checks import (
    check_choice,
    check_int,
    check_keys,
    check_pair,
    check_positive,
    check_real,
    finite_array,
    lane_array,
    lookup,
)
from ._cli import (
    PLOT_FORMATS,
    add_allow_slow,
    add_csv,
    add_unchecked,
    add_version,
    describe,
    int_at_least,
    name_value,
    nonnegative_float,
    output_dir,
    output_file,
    plot_file,
    positive_float,
    program,
    run_command,
    write_table,
)
from ._files import replacing, write_atomically
from ._glossary import GLOSSARY, glossary_table
from ._json import dumps, jsonable, write_json
from ._lazy import lazy_names
from ._processors import processors, tied_to_this_process
from ._progress import note, progress
from ._provenance import provenance
from ._results import RESULT_CLASSES, Result, from_dict, load, result
from ._status import Status

__all__ = [
    "GLOSSARY",
    "RESULT_CLASSES",
    "Result",
    "Status",
    "check_choice",
    "check_int",
    "check_keys",
    "check_pair",
    "check_positive",
    "check_real",
    "describe",
    "dumps",
    "finite_array",
    "from_dict",
    "glossary_table",
    "int_at_least",
    "jsonable",
    "lane_array",
    "lazy_names",
    "load",
    "lookup",
    "name_value",
    "nonnegative_float",
    "note",
    "output_dir",
    "output_file",
    "plot_file",
    "program",
    "provenance",
    "add_allow_slow",
    "add_csv",
    "add_unchecked",
    "add_version",
    "PLOT_FORMATS",
    "processors",
    "tied_to_this_process",
    "positive_float",
    "progress",
    "result",
    "run_command",
    "replacing",
    "write_atomically",
    "write_json",
    "write_table",
]
