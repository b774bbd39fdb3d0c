"""One name per quantity: the names of every argument, result field and JSON key.

The docs site's glossary page is ``glossary_table()``, rendered at every build
(docs/hooks.py); a test checks that every field of every result class is named here. Units are SI
and part of the name where the quantity has one (``_m``, ``_hz``, ``_s``).
"""

from __future__ import annotations

__all__ = ["GLOSSARY", "glossary_table"]

#: name: (meaning, unit, where the paper defines it)
GLOSSARY: dict[str, tuple[str, str, str]] = {
    # -- the excitation
    "frequency_hz": ("excitation frequency f_e (also: a frequency axis of a curve)", "Hz",
                     "Eq. 2.2"),
    "pa_frac": ("force amplitude P_a as a fraction of the weight Q", "1", "Fig. 2, 3 captions"),
    "p_a_n": ("force amplitude P_a (only at the low level: `simulate`, `steady_states`)", "N",
              "Eq. 2.2"),
    # -- the model
    "model": ("the model that made a result: its `parameters` and `effects`, as data", "",
              "Eq. 2.1-2.4"),
    "parameters": ("S, c_n, m2, h_n, l, M, g", "SI", "Section 2"),
    "effects": ("which laws and effects the model includes (contact loss, spring, damping, "
                "gravity)", "", "Eq. 2.1, 2.5"),
    "y0_m": ("static contact deflection y0 = delta0", "m", "Section 2"),
    "f_n0_hz": ("natural frequency f_n0 of the linearised system", "Hz", "Section 3"),
    "omega0_rad_s": ("omega0 = 2 pi f_n0", "rad/s", "Eq. 2.6"),
    "Q_n": ("weight of the slider Q = M g", "N", "Eq. 2.2"),
    "c_per_s": ("c of Eq. 2.6 (2c = S h_n y0^l / M)", "1/s", "Eq. 2.6"),
    "h_per_m_s2": ("eps h of Eq. 2.6 (quadratic stiffness over M)", "1/(m s^2)", "Eq. 2.6"),
    "damping_ratio": ("c / omega0", "1", "Eq. 2.6"),
    "G_per_P_a": ("G / P_a = 1 / M", "1/kg", "Eq. 2.6"),
    # -- a lane's state and fate
    "status": ("the lane's fate: -1 failed, 0 success (ran to the end; settled), 1 not "
               "settled, 2 under-resolved (`perturb.common.Status`)", "", ""),
    "message": ("why a lane has its status (empty when it succeeded)", "", ""),
    "settled": ("status is success: the stroboscopic state repeated within `tol` "
                "(derived from `status`)", "", "Section 2, end"),
    "failed": ("status is failed (derived from `status`)", "", ""),
    "y_init_m": ("initial displacement y", "m", "Eq. 2.4"),
    "v_init_m_s": ("initial velocity dy/dt", "m/s", "Eq. 2.4"),
    "y_final_m": ("displacement at the end of a run", "m", ""),
    "v_final_m_s": ("velocity at the end of a run", "m/s", ""),
    "y_start_m": ("displacement on the orbit at phase 0", "m", ""),
    "v_start_m_s": ("velocity on the orbit at phase 0", "m/s", ""),
    # -- what a period shows
    "app_m": ("peak-to-peak amplitude A_pp = ymax - ymin", "m", "Section 3, Fig. 2"),
    "ymin_m": ("least y over one period of the response (< 0: contact lost)", "m", "Fig. 3"),
    "ymax_m": ("largest y over one period of the response", "m", "Fig. 3"),
    "maxima_m": ("every local maximum of y over one period of the response", "m", "Fig. 3"),
    "minima_m": ("every local minimum of y over one period of the response", "m", "Fig. 3"),
    "contact_lost": ("ymin < 0: the slider leaves the slideway", "", "Eq. 2.1, Fig. 3b-j"),
    "period": ("p, the period of the orbit in excitation periods (0: none found)", "1", ""),
    "jumped": ("a sweep left its branch between this point and the one before (a fold "
               "lies between them: Section 3.3's jumps)", "", "Section 3.3"),
    "multipliers": ("Floquet multipliers of the orbit (stable inside the unit circle); "
                    "JSON: {real, imag}", "1", ""),
    "method": ("the route to a steady state: newton, march+newton, march, none; series (a "
               "scene's series route: nothing simulated)", "", ""),
    "extrema": ("per lane, rows (phase [periods], y [m], +1 maximum / -1 minimum)", "", ""),
    "history_phase": ("phase of each stored step, in periods since the recording began",
                      "1", ""),
    "history_y_m": ("y after every step of the recorded periods", "m", ""),
    "history_v_m_s": ("dy/dt after every step of the recorded periods", "m/s", ""),
    # -- accuracy and cost
    "steps_per_period": ("RK4 steps per excitation period asked for ('auto': at least 128, "
                         "and omega0 dt <= 0.5)", "1", "Section 2"),
    "app_rtol": ("bound on App's estimated relative step error; above it a lane is refined, "
                 "then under-resolved", "1", ""),
    "steps_used": ("RK4 steps per period a lane's result comes from (after refinement)", "1",
                   ""),
    "periods": ("excitation periods run in all", "1", ""),
    "record_periods": ("final periods the recorded observables cover", "1", ""),
    "periods_run": ("excitation periods integrated for a lane (its cost)", "1", ""),
    "tol": ("relative tolerance of the settling test", "1", ""),
    "max_periods": ("cap of time marching per lane, in periods (None: 30 decay times 1/c)",
                    "1", ""),
    "refinements": ("how many times a lane that failed, did not settle, settled with p > 1 "
                    "or under-resolved is solved again with twice the steps", "1", ""),
    "unchecked": ("a study taken past the ranges of f_e, P_a and the contact where the answers "
                  "are measured to hold (numerics.simulation.ranges)", "", ""),
    "tolerance": ("a relative error bound (validity of a series, parting of two models)", "1",
                  ""),
    "truncation": ("which terms of the equation in contact a series keeps: consistent (every "
                   "k_j u^j at eps^(j-1) and d_j u^j u' at eps^j up to its order) or paper "
                   "(Eq. 2.6: h u^2 and linear damping); absent: paper", "", "Eq. 2.5, 2.6"),
    "alpha": ("what the backbone series' variable is: a / y0 (consistent) or h a / omega0^2 "
              "(Eq. 2.6's series)", "", "Eq. 2.7"),
    "elapsed_s": ("wall time of the computation", "s", ""),
    "max_checked_steps": ("a sweep checks its jumps with the full model where it has at most "
                          "this many steps between neighbours whose App changes by more than "
                          "1.3x; past it none (`jumped` null), 0: no check", "1", ""),
    "steady_options": ("the steady-state engine's decisions that differ from the defaults: "
                       "fields of `numerics.SteadyOptions` beyond the accuracy ones (only "
                       "when some differ)", "", ""),
    "provenance": ("where a result file comes from: the toolkit's `version` and `commit` (in a "
                   "git checkout; \"+changes\" when its files differ from it), the `python` "
                   "and `libraries` versions, and when it was `written_utc`", "", ""),
    "settings": ("the settings a result was computed with", "", ""),
    "kind": ("JSON only: the class of the result, for `load`; of a bifurcation: fold or "
             "period-doubling", "", ""),
    # -- sweeps and the census
    "direction": ("sweep direction: up or down", "", "Section 2, end"),
    "runs": ("the runs of a sweep, one per (pa_frac, direction)", "", ""),
    "lanes": ("every lane of the census, with its status", "", ""),
    "attractors": ("the distinct steady states of a census, largest basin first", "",
                   "Section 3.3"),
    "basin_fraction": ("fraction of the census's initial states that reach the attractor",
                       "1", ""),
    "not_settled_fraction": ("fraction of initial states whose lane did not settle", "1", ""),
    "dominant_harmonic": ("frequency of the strongest acceleration harmonic, over f_e", "1",
                          "Section 3.2"),
    "label": ("primary, 1/m superharmonic or period-p, from the dominant harmonic", "",
              "Eq. 3.1"),
    "orbit_y_m": ("y after every step of one orbit", "m", ""),
    # -- the exact backbone, Fig. 4, Fig. 5, the backbone series (numerics)
    "u_max_m": ("largest compression beyond y0, y_max - y0: the energy level of a free "
                "oscillation", "m", "Section 3.1"),
    "a1_m": ("amplitude of the fundamental harmonic of y(t) (the a1 of the series)", "m",
             "Eq. 2.7"),
    "contact_loss_app_m": ("A_pp of the free oscillation at which contact is first lost "
                           "(y_min = 0)", "m", "Eq. 2.1"),
    "points": ("how many levels, heights or frequencies a curve is computed at", "1", ""),
    "nodes": ("Chebyshev-Lobatto intervals per period integral of the exact backbone", "1", ""),
    "app_range_m": ("(lo, hi): the A_pp range an exact backbone covers", "m", "Fig. 2"),
    "phase": ("phase within the excitation period, in periods", "1", ""),
    "y_m": ("displacement y over one period", "m", "Eq. 2.4"),
    "v_m_s": ("velocity dy/dt over one period", "m/s", "Eq. 2.4"),
    "reaction_n": ("reaction of the contact R = F_s + F_d (< 0 while it pushes the slider up)",
                   "N", "Eq. 2.1"),
    "damping_n": ("damping part F_d of the reaction", "N", "Eq. 2.1"),
    "pressure_pa": ("normal contact pressure p = -R / S, positive in compression", "Pa", "Fig. 5"),
    "loop_area_j": ("area of the hysteresis loop in the (y, R) plane", "J", "Fig. 5"),
    "dissipated_j": ("energy the damping force dissipates over one period", "J", "Fig. 5"),
    "drive_work_j": ("work of the drive P over one period", "J", "Eq. 2.2"),
    "closure": ("relative change of the state over the last period: how steady a loop is", "1",
                ""),
    "height_m": ("height h_b of a steel body standing on the contact", "m", "Fig. 4"),
    "mass_kg": ("mass M = rho S h_b of that body", "kg", "Fig. 4"),
    "density_kg_m3": ("density rho of steel, from the paper's cube (M / side^3)", "kg/m^3",
                      "Section 2"),
    "paper_height_m": ("height of the body the paper measured, its 30 mm cube", "m", "Section 2"),
    "paper_f_n0_hz": ("natural frequency the paper reports for its body", "Hz", "Section 3"),
    "orders": ("orders N of the perturbation series", "1", "Eq. 2.7"),
    "exact_hz": ("frequency of the exact backbone (free oscillation)", "Hz", "Section 3.1"),
    "series_hz": ("frequency of the backbone series of an order, at the same a1", "Hz", "Eq. 2.7"),
    "relative_error": ("relative error, abs(value / reference - 1)", "1", ""),
    "limit_a1_m": ("a1 up to which a series order holds: within `tolerance`, in contact", "m", ""),
    "limit_app_m": ("A_pp up to which a series order holds: within `tolerance`, in contact", "m",
                    ""),
    "crossing_a1_m": ("a1 where a series order's error first exceeds `tolerance`", "m", ""),
    "crossing_app_m": ("A_pp where a series order's error first exceeds `tolerance`", "m", ""),
    # -- the perturbation series and its frequency response (perturb)
    "order": ("order N of the perturbation series (highest power of eps, or of alpha for "
              "the backbone series)", "1", "Eq. 2.7"),
    "branches": ("the branches of a result: of a Response, the roots of the frequency "
                 "equation, branch j holding the (j+1)-th largest omega at each frequency; of "
                 "a Continuation, the continued orbits", "", "Eq. 2.7, Fig. 2"),
    "a0_m": ("amplitude A0 = G H_1(omega) of u0, the order-0 fundamental", "m", "Eq. 2.8"),
    "omega_rad_s": ("non-linear natural frequency omega, a root of the frequency equation",
                    "rad/s", "Eq. 2.7"),
    "u_min_m": ("least u = y - y0 over one period (y0 + u_min_m <= 0: contact lost)", "m",
                "Eq. 2.6"),
    "valid": ("the series is accurate here: error_estimate < tolerance and contact kept; "
              "not a statement of stability (a valid root can be an unstable orbit)", "",
              ""),
    "error_estimate": ("estimated relative error of A_pp from the next two orders of the "
                       "series and, for Eq. 2.6's series off the paper's contact, its "
                       "distance to the consistent series (null: no root of those orders "
                       "nearby, no estimate)", "1", ""),
    "amplitude": ("what the amplitude a of the backbone series is: first-harmonic, the "
                  "amplitude of the fundamental", "", "Eq. 2.7"),
    "coefficients": ("exact coefficients c_k of omega/omega0 = sum_k c_k alpha^k (alpha: "
                     "see alpha); JSON: strings such as \"-5/12\". In a derived series' "
                     "JSON: each k_j, d_j it keeps, in closed form", "1", ""),
    "waveform": ("cosine coefficients of x_1 .. x_(N+1) of the backbone series, "
                 "x = alpha u / a; JSON: strings", "1", ""),
    "omega_range": ("(lo, hi): where the roots omega are sought, in units of omega0", "1",
                    ""),
    "grid_points": ("uniform grid points in omega_range before refining the roots", "1", ""),
    "samples": ("samples per period of the reconstructed u(t)", "1", ""),
    # -- the comparison of the series with RK4
    "model_name": ("which RK4 model a curve comes from: eq26 (Eq. 2.6) or full (Eq. 2.1-2.4)",
                   "", "Eq. 2.4, 2.6"),
    "curves": ("RK4 steady states per (model_name, pa_frac), swept up and down", "", ""),
    "responses": ("the series of each order against one RK4 curve", "", ""),
    "backbone": ("the series backbones of each order against the exact backbone", "", ""),
    "notes": ("what happened along the way that a reader should know", "", ""),
    "rk4_app_m": ("App of a settled RK4 steady state", "m", "Fig. 2"),
    "series_app_m": ("App of the valid series response nearest to that state", "m", "Eq. 2.7"),
    "unmatched": ("a state where the series is valid but no response of it lies near", "", ""),
    "largest_error": ("largest relative error of App where the series is valid", "1", ""),
    "largest_matched_error": ("the same over the states that the series matches", "1", ""),
    "peaks": ("the primary, 1/2 and 1/3 superharmonic peaks, from RK4 and the series", "",
              "Eq. 3.1"),
    "k": ("the resonance f_e ~ f_n0 / k (1: primary, k > 1: superharmonic)", "1", "Eq. 3.1"),
    "rk4_hz": ("place of a peak in the RK4 steady states", "Hz", "Fig. 2"),
    # -- the parameters and effects inside `model`
    "S": ("nominal (apparent) contact area", "m^2", "Eq. 2.1"),
    "c_n": ("contact stiffness coefficient", "N/m^(m2+2)", "Eq. 2.1"),
    "m2": ("exponent of the spring law F_s = -S c_n y^m2", "1", "Eq. 2.1"),
    "h_n": ("contact damping coefficient", "N s/m^(l+3)", "Eq. 2.1"),
    "l": ("exponent of the damping law F_d = -S h_n y^l dy/dt", "1", "Eq. 2.1"),
    "M": ("mass of the slider", "kg", "Eq. 2.2"),
    "g": ("acceleration of gravity", "m/s^2", "Eq. 2.2"),
    "contact_loss": ("(in effects) the contact force vanishes for y <= 0; (in results) "
                     "ymin < 0", "", "Eq. 2.1"),
    "spring": ("spring law: power, taylor (degree taylor_degree about y0) or linear", "",
               "Eq. 2.1, 2.5"),
    "taylor_degree": ("degree of the Taylor spring about y0", "1", "Eq. 2.5"),
    "damping": ("damping law: power, or linear (linearised at y0)", "", "Eq. 2.1, 2.5"),
    "gravity": ("whether the weight Q presses the slider on the slideway", "", "Eq. 2.3"),
    # -- settings
    "record": ("the observables a simulation records: final, minmax, extrema, history", "",
               ""),
    "max_extrema": ("room for local extrema per lane of a simulation", "1", ""),
    "grid": ("the census's initial states, in units of y0 and omega0 y0", "", ""),
    "y_over_y0": ("initial displacements of the census, over y0", "1", ""),
    "v_over_omega0_y0": ("initial velocities of the census, over omega0 y0", "1", ""),
    "initial_states": ("how many initial states the census starts from", "1", ""),
    "cluster_tol": ("states closer than this fraction of App are one attractor", "1", ""),
    "cluster_floor_y0": ("... of App, but never of less than this fraction of y0", "1", ""),
    "rest_fraction_y0": ("an orbit with App below this fraction of y0 is rest", "1", ""),
    # -- the multistability atlas: arrays and lists over cells, shape (P_a, f_e)
    "attractor_count": ("per cell of the atlas, the distinct attractors the census finds "
                        "(-1: the cell's task failed)", "1", "Section 3.3"),
    "attractor_periods": ("per cell of the atlas, the period p of each attractor, largest "
                          "basin first", "1", ""),
    "attractor_labels": ("per cell of the atlas, the label of each attractor", "", "Eq. 3.1"),
    "attractor_basins": ("per cell of the atlas, the basin fraction of each attractor", "1", ""),
    "attractor_app_m": ("per cell of the atlas, App of each attractor", "m", "Fig. 2"),
    "cells": ("the atlas's grid: [frequencies, amplitudes]", "1", ""),
    "tasks": ("how many tasks (blocks of consecutive cells) the atlas was cut into", "1", ""),
    "tasks_retried": ("how many tasks ran again on a fresh pool after a worker process died",
                      "1", ""),
    "cell_time_s": ("the atlas's wall time per cell", "s", ""),
    "workers": ("an atlas scene's worker processes on this machine (null: one per processor)",
                "1", ""),
    "overlay_folds": ("an atlas scene also continues the fold curves of its box and draws "
                      "them over the map", "", "Section 3.3"),
    "models": ("the effects of each RK4 model of the comparison, by model_name", "", ""),
    # -- derived values in the JSON
    "height_ratio": ("series_app_m / rk4_app_m of a peak", "1", ""),
    "unmatched_hz": ("frequencies of the unmatched states", "Hz", ""),
    "parting": ("per pa_frac, where the full model's App parts from Eq. 2.6's", "", ""),
    "states": ("states where both models settled", "1", ""),
    "differ": ("states where App differs by more than tolerance", "1", ""),
    "differ_with_contact_loss": ("... of them with contact lost", "1", ""),
    "differ_in_contact": ("... of them in contact (the damping law)", "1", ""),
    "in_contact_hz": ("frequencies where the models differ in contact", "Hz", ""),
    # -- scenes (numerics.scenes, docs/scenes.md)
    "keep_orbits": ("also keep y after every step of each orbit (`orbit_y_m`)", "", ""),
    "title": ("a scene's title", "", ""),
    "source": ("the scene file a run was read from", "", ""),
    "study": ("the kind of a scene's study: sweep, attractors, time_history, hysteresis, "
              "analytic_response, backbone, derivation, natural_frequency, comparison",
              "", ""),
    "options": ("the options of a scene's study, defaults filled in", "", ""),
    "model_overrides": ("the model parameters a scene or `--set` replaces, by name", "SI", ""),
    "observables": ("the observables a scene asks for; in a result, one dict per curve",
                    "", ""),
    "figures": ("figure kind: file name, written into the output folder", "", ""),
    "json": ("file name of a scene's JSON result, in the output folder", "", ""),
    "text": ("what a study printed (the derivation), or its file name", "", ""),
    "animation": ("a scene's GIF: kind (sweep or slider), frames, fps, frequency_hz", "", ""),
    "frames": ("frames of an animation", "1", ""),
    "fps": ("frames per second of an animation", "1/s", ""),
    "recorder": ("what the simulator recorded for a scene (only what its observables need)",
                 "", ""),
    "route": ("how a scene was computed: full model, reduced model, series (its studies, or "
              "chosen by effects = \"auto\") or closed form", "", ""),
    "outcomes": ("the result objects a scene's study made, as the Python API returns them",
                 "", ""),
    "selection": ("effects = \"auto\": per effect, the change of each observable when it is "
                  "switched off, and the verdict", "", ""),
    "selection_note": ("effects = \"auto\": the route chosen, its check against the full "
                       "model, the times", "", ""),
    "effect": ("an effect (and the simpler law tried for it) in the auto table", "", ""),
    "change": ("largest change of each observable from the full model, over the curve's "
               "scale (App; the largest harmonic; the contact fraction as is)", "1", ""),
    "own_change": ("the change of each observable from the model of the auto table's row "
                   "above: what the effect alone adds", "1", ""),
    "verdict": ("kept or dropped (and why it could not be dropped); for the series, taken "
                "as the route, not taken (and why) or not a candidate (and why)", "", ""),
    "seconds": ("time of a run on the auto sample", "s", ""),
    "files": ("the files a scene wrote, relative to its output folder", "", ""),
    "app": ("observable: peak-to-peak amplitude A_pp", "", "Fig. 2"),
    "spectrum": ("observable: amplitudes of the harmonics of one response period", "", ""),
    "spectrum_m": ("amplitudes of the harmonics k f_e / p of one period (k = 0: the mean)",
                   "m", ""),
    "contact_fraction": ("fraction of the period spent out of contact (y <= 0)", "1",
                         "Eq. 2.1"),
    "time_history": ("observable: y and v after every step", "", ""),
    "phase_portrait": ("observable: v against y over the response period", "", ""),
    "hysteresis": ("observable: contact pressure against y over a period", "", "Fig. 5"),
    "time_s": ("time of each sample of a history", "s", ""),
    "extrema_m": ("every local extremum of y over the recorded periods", "m", ""),
    "quick": ("coarser grids (the tests)", "", ""),
    "real": ("JSON of a complex array: its real part", "", ""),
    "imag": ("JSON of a complex array: its imaginary part", "", ""),
    # -- continuation
    "bifurcations": ("folds and period doublings met along continued branches: kind, "
                     "frequency_hz, app_m, pa_frac, located, frequency_tol_hz, pa_frac_tol",
                     "", ""),
    "located": ("a bifurcation located by Brent's method between two points of its branch "
                "(true), or only marked at a point within one step of it (false: Newton "
                "cannot correct between the two, a corner of the map); null: unknown, read "
                "from a file saved before it was recorded", "", ""),
    "frequency_tol_hz": ("how far a bifurcation of the N-step period map may lie from its "
                         "frequency_hz: Brent's tolerance when located (a fold curve's "
                         "fold: the round-off of the period map), the step's reach in f_e "
                         "when only marked, at least 1e-4 f_n0 at a fold about which f "
                         "zigzags (the map's corners); 0 when f_e was held fixed; null: "
                         "unknown, read from a file saved before it was recorded", "Hz", ""),
    "pa_frac_tol": ("how far a bifurcation may lie from its pa_frac (as frequency_tol_hz, "
                    "in P_a / Q); 0 when P_a was held fixed", "1", ""),
    "stable": ("per point of a continued branch, or per root of the series (null where "
               "unknown): both Floquet multipliers inside the unit circle", "", ""),
    "fmin_hz": ("lower end of the band of f_e a branch is continued in", "Hz", ""),
    "fmax_hz": ("upper end of the band of f_e a branch is continued in", "Hz", ""),
    "ds_max": ("largest continuation step, in the scaled unknowns (y/y0, v/(omega0 y0), "
               "f/f_n0), for orbits within twice the static deflection; where the branch "
               "runs straight on a larger orbit, up to ds_max times half the orbit's size "
               "sqrt(y^2 + v^2) in those units, at most 20 ds_max", "1", ""),
    "max_angle": ("largest angle between the tangents of consecutive continued points, "
                  "except over a step shorter than the map's corner step (1e-3 in the "
                  "unknowns on orbits within twice the static deflection, in proportion "
                  "to the orbit's size on larger ones, at most 20 times and at most "
                  "ds_max: `corner_step`), where a larger turn is taken for a corner "
                  "and accepted",
                  "rad", ""),
    "max_points": ("most points a walk of a continued branch may take (the folds located "
                   "once it has ended come on top)", "1", ""),
    "engine": ("how a sweep, a walk or the analytic response runs: 'compiled' (machine "
               "code) or 'python' / 'numpy' (the reference); 'auto' takes the compiled route "
               "where it is built or builds within seconds (the walk), the reference "
               "otherwise (`make compiled` builds the rest)", "", ""),
    "walk_options": ("the tuning a walk ran with: the fields of `numerics.WalkOptions` "
                     "(step control and corrector), each documented there", "", ""),
    "switched_at_hz": ("the period doublings a period-2p branch was switched onto at "
                       "(branch switching)", "Hz", ""),
    "continued_in": ("the parameter a continuation scene follows its orbits in: "
                     "frequency_hz (one branch set per P_a) or pa_frac (one per f_e)", "", ""),
    "switch_branches": ("a continuation scene also continues the period-2p branch born at "
                        "each period doubling", "", ""),
    # -- fold curves in the (f_e, P_a) plane
    "fold_curves": ("fold curves of period-1 orbits continued in (f_e, P_a): per point "
                    "frequency_hz, pa_frac, app_m, multipliers, state", "", "Section 3.3"),
    "cusps": ("where the two folds of one resonance meet: the least P_a of its bistable "
              "region", "", "Section 3.3"),
    "seeds": ("the folds located by one-parameter continuation that fold curves start from",
              "", ""),
    "resonance": ("m of the resonance f_n0 / m a fold curve bounds (1 primary, 2 the 1/2 "
                  "superharmonic; 0 unknown: no cusp in the box)", "1", "Section 3"),
    "pa_min": ("lower end of a range of P_a / Q (fold curves, atlas, continuation in P_a)",
               "1", ""),
    "pa_max": ("upper end of a range of P_a / Q (fold curves, atlas, continuation in P_a)",
               "1", ""),
    "seed_pa_fracs": ("the P_a / Q at which folds are sought to start fold curves from", "1",
                      ""),
    # -- the stability of the series' roots
    "orbit_distance": ("how far the RK4 orbit of Eq. 2.6 that Newton reached from a series "
                       "root's state lies from it: abs(dy) / (App/2) + abs(dv) / (Omega App/2)",
                       "1", ""),
    "reach": ("how far (in units of the series' error estimate, plus RK4's own error) the "
              "RK4 orbit may lie from a series root's state and still give it a stability "
              "flag", "1", ""),
    # -- the largest Lyapunov exponent
    "exponent_per_s": ("largest Lyapunov exponent lambda: the mean growth rate of a small "
                       "perturbation, by Benettin's method on the RK4 map's tangent", "1/s",
                       ""),
    "exponent_per_period": ("lambda T = lambda / f_e: the perturbation's log growth per "
                            "drive period", "1", ""),
    "error_per_s": ("error estimate of lambda: the largest of the block means' standard "
                    "error, half the gap between the run's halves, and ln(K) / (K T) after K "
                    "periods", "1/s", ""),
    "error_per_period": ("error_per_s / f_e", "1", ""),
    "block_exponent_per_s": ("lambda over each block of consecutive periods of the run",
                             "1/s", ""),
    "lyapunov": ("the largest Lyapunov exponent of each census lane that did not settle "
                 "(a LyapunovExponents)", "", ""),
    "lyapunov_lanes": ("the positions, among the census's lanes, of the lanes whose exponent "
                       "`lyapunov` holds", "1", ""),
    "lyapunov_periods": ("drive periods over which a census measures the largest Lyapunov "
                         "exponent of each lane that did not settle (null: not measured)",
                         "1", ""),
    "chaotic_fraction": ("share of the initial states whose lane is chaotic: largest "
                         "Lyapunov exponent above 3 error estimates", "1", ""),
    "motion": ("what lambda says: chaotic (lambda > 3 error), periodic or transient "
               "(lambda < -3 error) or undecided (quasi-periodic included)", "", ""),
    "discard_periods": ("periods run before lambda is measured (the tangent turns into the "
                        "most expanding direction)", "1", ""),
    "blocks": ("how many blocks of periods the run of lambda is split into for its error",
               "1", ""),
}


def glossary_table() -> str:
    """The glossary as a Markdown table (the docs site's glossary page)."""
    rows = ["| name | meaning | unit | paper |", "|---|---|---|---|"]
    rows += ["| " + " | ".join([f"`{name}`", *map(_cell, entry)]) + " |"
             for name, entry in GLOSSARY.items()]
    return "\n".join(rows)


def _cell(text: str) -> str:
    """``text`` as one Markdown table cell (a | in it would end the cell)."""
    return text.replace("|", "\\|")
