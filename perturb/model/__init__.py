"""The physical model of Eq. 2.1-2.4, once, and Eq. 2.6 derived from it.

- ``parameters``: the paper's numbers (``PAPER``, ``ContactParameters``);
- ``symbols``: the model's named symbols; ``effects``: which physical effects it has;
- ``contact_model``: ``ContactModel``, the model as sympy expressions;
- ``eq26`` and ``numbers``: Eq. 2.6 derived (``Eq26``) and its numbers at a parameter
  set (``eq26_numbers``, kept on disk so that no sympy is needed the next time);
- ``set_option``: ``--set NAME=VALUE`` on every command line.
"""

from perturb.common import lazy_names

# Imported at first use (PEP 562): importing one module of the folder loads no other.
_LAZY = {
    "ContactModel": ".contact_model",
    "Effects": ".effects",
    "FULL": ".effects",
    "EQ_2_6": ".effects",
    "LINEAR": ".effects",
    "ContactParameters": ".parameters",
    "PAPER": ".parameters",
    "parameters_with": ".parameters",
    "Eq26": ".eq26",
    "Eq26Numbers": ".numbers",
    "eq26_numbers": ".numbers",
}

__getattr__, __dir__ = lazy_names(__name__, _LAZY, globals())

__all__ = [
    "ContactModel",
    "ContactParameters",
    "EQ_2_6",
    "Effects",
    "Eq26",
    "Eq26Numbers",
    "FULL",
    "LINEAR",
    "PAPER",
    "eq26_numbers",
    "parameters_with",
]
