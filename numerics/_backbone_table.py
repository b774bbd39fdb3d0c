"""The exact backbone as `python -m numerics backbone` prints it."""

from __future__ import annotations

import numpy as np

from ._backbone import Backbone

__all__ = ["format_backbone"]


def format_backbone(backbone: Backbone, rows: int = 12) -> str:
    """A summary line and a table of at most ``rows`` levels, evenly picked.

    Examples
    --------
    >>> from numerics import exact_backbone
    >>> print(format_backbone(exact_backbone([1e-9, 4e-7]), rows=2))  # doctest: +ELLIPSIS
    Backbone: 2 points, ...
          A_pp [nm]      a1 [nm]       f [Hz]  contact lost
            2.00148      1.00074     1485.588  no
            1606.29      737.992      801.872  yes
    """
    picked = np.unique(np.linspace(0, backbone.app_m.size - 1, rows).round().astype(int))
    lines = [str(backbone), f"{'A_pp [nm]':>15}{'a1 [nm]':>13}{'f [Hz]':>13}  contact lost"]
    for i in picked:
        lines.append(
            f"{backbone.app_m[i] * 1e9:>15.6g}{backbone.a1_m[i] * 1e9:>13.6g}"
            f"{backbone.frequency_hz[i]:>13.3f}  {'yes' if backbone.contact_lost[i] else 'no'}"
        )
    return "\n".join(lines)
