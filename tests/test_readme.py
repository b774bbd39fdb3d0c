"""The README's shape; its examples themselves run through sybil (``conftest.py``)."""

import re
from pathlib import Path

README = (Path(__file__).parents[1] / "README.md").read_text(encoding="utf-8")


def test_python_examples_are_sessions_that_show_their_output():
    # A ```python block would only be run, not checked: the README uses ```pycon.
    assert not re.findall(r"```python\n", README)
    assert len(re.findall(r"```pycon\n", README)) >= 1


def test_readme_opens_with_the_two_commands():
    head = README[:1200]
    assert "make paper" in head and "make test" in head
