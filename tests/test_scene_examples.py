"""The lecturer's example scenes (issue 11, item 7): each runs and writes its figures."""

import dataclasses
from pathlib import Path

import pytest
from PIL import Image

from numerics.scenes import read_scene, run_scene

EXAMPLES = sorted((Path(__file__).parent.parent / "numerics" / "scenes" / "examples")
                  .glob("*.toml"))
#: Frames of an example's animation in the tests (the scene asks for more).
TEST_FRAMES = 6


def test_there_are_the_nine_examples_the_gallery_shows():
    names = {p.stem for p in EXAMPLES}
    assert names == {"linear-contact", "superharmonic-birth", "bouncing", "other-contact",
                     "effects-at-740hz", "continuation", "folds", "atlas",
                     "softer-contact-backbone"}


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.stem)
def test_each_example_runs_and_writes_its_figures(path, tmp_path):
    scene = read_scene(path)
    assert scene.description.strip(), "an example says what it shows"
    if scene.animation:
        scene = dataclasses.replace(scene, animation={**scene.animation, "frames": TEST_FRAMES})
    if scene.study == "atlas":  # in this process: the tests share the machine
        scene = dataclasses.replace(scene, options={**scene.options, "workers": 1})
    run = run_scene(scene, out=tmp_path)
    assert run.outcomes and all(o.summary() for o in run.outcomes)
    expected = list(scene.figures.values())
    assert run.files[: len(expected)] == expected
    for name in run.files:
        assert (tmp_path / name).stat().st_size > 1000, name
        if name.endswith(".gif"):
            assert Image.open(tmp_path / name).n_frames == TEST_FRAMES


def test_the_bouncing_example_loses_contact_and_the_linear_one_cannot():
    bouncing = run_scene(read_scene(EXAMPLES[0].parent / "bouncing.toml"))
    fraction = bouncing.observables[0]["contact_fraction"]
    assert (fraction > 0).all()  # at 0.5 Q over 900-1500 Hz the slider flies every period
    linear = read_scene(EXAMPLES[0].parent / "linear-contact.toml")
    assert linear.effects.contact_loss is False and linear.effects.spring == "linear"


def test_the_orbit_examples_show_folds_a_cusp_and_coexisting_attractors():
    """What each description promises: the primary peak at 0.05 Q folds twice (continue_orbits'
    docstring: 1420 and 1373 Hz), its fold curves meet at one cusp near 0.033 Q (fold_curves'
    docstring: 1442 Hz, 0.0334 Q), and somewhere on the small atlas attractors coexist."""
    folder = EXAMPLES[0].parent
    continued = run_scene(read_scene(folder / "continuation.toml")).outcomes[0]
    assert [round(b.frequency_hz) for b in continued.folds()] == [1420, 1373]
    cusps = run_scene(read_scene(folder / "folds.toml")).outcomes[0].cusps
    assert [(c.resonance, round(c.pa_frac, 3)) for c in cusps] == [(1, 0.033)]
    scene = read_scene(folder / "atlas.toml")
    scene = dataclasses.replace(scene, options={**scene.options, "workers": 1})
    found = run_scene(scene).outcomes[0]
    assert found.attractor_count.shape == (4, 6) and found.attractor_count.max() >= 2
