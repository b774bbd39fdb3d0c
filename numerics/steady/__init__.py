"""Steady states and what is built on them: sweeps, the attractor census, the atlas.

- ``shooting``: ``steady_states``, Newton shooting on the period map with time marching
  as fallback, the settling test and the step-error estimate (the steady-state engine:
  the compiled sweep, ``kernels/sweep_template``, takes its constants from here);
- ``options``: ``SteadyOptions``, the settings of both routes (accuracy and the engine's
  decisions), one object;
- ``orbits``: ``Orbits``, the one record of steady-state observables;
- ``sweeps`` and ``sweep_compiled``: ``sweep``, frequency sweeps up and down (Fig. 2, 3);
- ``census``: ``attractor_census``, which steady states coexist and their basins
  (``Census``; ``attractors``, its deprecated name);
- ``lyapunov``: ``largest_lyapunov``, chaos told apart from slow transients;
- ``multistability``: ``atlas``, the census over a grid of (f_e, P_a) on any Executor.
"""

from perturb.common import lazy_names

# Imported at first use (PEP 562): importing one module of the folder loads no other.
_LAZY = {
    "SteadyStates": ".shooting",
    "steady_states": ".shooting",
    "Orbits": ".orbits",
    "SteadyOptions": ".options",
    "Sweep": ".sweeps",
    "SweepRun": ".sweeps",
    "sweep": ".sweeps",
    "Attractor": ".census",
    "Census": ".census",
    "attractor_census": ".census",
    "attractors": ".census",
    "LyapunovExponents": ".lyapunov",
    "largest_lyapunov": ".lyapunov",
    "classify_motion": ".lyapunov",
    "Atlas": ".multistability",
    "atlas": ".multistability",
}

__getattr__, __dir__ = lazy_names(__name__, _LAZY, globals())

__all__ = [
    "Atlas",
    "Attractor",
    "Census",
    "LyapunovExponents",
    "Orbits",
    "SteadyOptions",
    "SteadyStates",
    "Sweep",
    "SweepRun",
    "atlas",
    "attractor_census",
    "attractors",
    "classify_motion",
    "largest_lyapunov",
    "steady_states",
    "sweep",
]
