# `make paper` and `make test` each set up everything on a fresh machine.
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed

.PHONY: paper test test-slow bench lint figures compiled docs clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e '.[test]'
	touch $(STAMP)

paper: $(STAMP)
	$(PY) -m paper_checks --out out

test: $(STAMP)
	$(PY) -m pytest -q

test-slow: $(STAMP)
	$(PY) -m pytest -q -m slow

DOCS_STAMP := $(VENV)/.docs-installed

$(DOCS_STAMP): $(STAMP)
	$(PY) -m pip install --quiet -e '.[docs]'
	touch $(DOCS_STAMP)

# The documentation site, into out/site; a warning (a broken link, a page left out of
# the navigation, a docstring that does not parse) fails the build.
docs: $(DOCS_STAMP)
	NO_MKDOCS_2_WARNING=1 $(PY) -m mkdocs build --strict --quiet

BENCH_STAMP := $(VENV)/.bench-installed

$(BENCH_STAMP): $(STAMP)
	$(PY) -m pip install --quiet -e '.[bench]'
	touch $(BENCH_STAMP)

bench: $(BENCH_STAMP)
	$(PY) -m tests.benchmarks --record docs/benchmarks.json

# Opt in to the compiled routes for the paper's model: the sweep driver and the order-6
# response kernels of both truncations (tens of seconds each to build: bench_sweep's,
# bench_perturb's and bench_truncation's rows), which engine="auto" takes once they are
# in the cache.
compiled: $(STAMP)
	$(PY) -c "from numerics import sweep; sweep([1000.0], 0.1, engine='compiled')"
	$(PY) -c "from perturb import frequency_response as r; r([1000.0], 0.1, 6, engine='compiled')"
	$(PY) -c "from perturb import frequency_response as r; r([1000.0], 0.1, 6, engine='compiled', truncation='paper')"

# The README's figures, redrawn by the command line.
figures: $(STAMP)
	$(PY) -m numerics sweep --quiet --plot docs/figures/fig2-app.png
	mv docs/figures/fig2-app-extrema.png docs/figures/fig3-extrema.png
	$(PY) -m numerics continue --pa-frac 0.05 --fmin 1300 --fmax 1600 --quiet \
	  --plot docs/figures/continuation-005q.png > /dev/null
	$(PY) -m numerics folds --fmin 300 --fmax 1600 --pa-min 0.02 --pa-max 0.8 \
	  --seed-pa-frac 0.8 0.65 0.4 0.06 --quiet \
	  --plot docs/figures/folds.png > /dev/null
	$(PY) -c "from numerics import continue_orbits; from numerics.plots import plot_continued_app; \
	from perturb import PAPER_PANEL_FRACTIONS as fracs; \
	plot_continued_app([continue_orbits(f, 250.0, 1800.0) for f in fracs], \
	'docs/figures/fig2-continued.png')"
	$(PY) -c "from numerics import attractor_census; from numerics.plots import plot_census; \
	plot_census(attractor_census(490.0, 0.5), 'docs/figures/census-490hz.png')"
	$(PY) -c "from numerics import atlas, fold_curves; from numerics.plots import plot_atlas; \
	plot_atlas(atlas(1150.0, 1550.0, 0.02, 0.08, grid=(41, 16)), 'docs/figures/atlas.png', \
	folds=fold_curves(1150.0, 1550.0, 0.02, 0.08))"
	$(PY) -c "import numpy as np; from numerics import exact_backbone; \
	from numerics.plots import plot_backbone_truncations as plot; \
	from perturb import PAPER, ContactModel, backbone_series, eq26_numbers, parameters_with; \
	y0 = eq26_numbers().y0_m; contacts = [parameters_with({'m2': m, 'c_n': PAPER.Q_n / \
	(PAPER.S * y0 ** m)}) for m in (1.5, 2.0, 2.5)]; \
	plot([(exact_backbone(y0 * np.geomspace(0.01, 0.6, 60), model=ContactModel(p)), \
	backbone_series(8, parameters=p), backbone_series(8, 'paper', p)) for p in contacts], \
	'docs/figures/backbone-truncations.png')"
	for scene in numerics/scenes/examples/*.toml; do \
	  $(PY) -m numerics scene $$scene --quiet --out docs/figures/examples > /dev/null || exit 1; \
	done

lint: $(STAMP)
	$(VENV)/bin/ruff check perturb numerics paper_checks tests

clean:
	rm -rf $(VENV) out
