# Two commands on a fresh machine with Python 3.11, 3.12 or 3.13: `make figures` and `make test`.
# Each creates the virtual environment in .venv on first use.

PYTHON ?= python3
override VENV := .venv
PY := $(VENV)/bin/python
READY := $(VENV)/.installed
EXTRAS := $(VENV)/.extras-installed
NOTEBOOKS := $(sort $(wildcard notebooks/*.ipynb))

.PHONY: figures test unit notebooks-check notebooks lab book book-check ledger benchmark mutations benchmark-maps benchmark-budgets warehouses pogema-crosscheck reproduce verify clean-env clean-cache

$(READY): requirements.txt pyproject.toml
	@$(PYTHON) -c 'import sys; sys.exit(sys.version_info < (3, 11) and "glamas needs Python >= 3.11: set PYTHON=python3.11")'
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -r requirements.txt
	touch $@

# The optional extras (Dask backend, PettingZoo adapter) have tests of their own.
$(EXTRAS): $(READY) requirements-extras.txt
	$(PY) -m pip install --quiet -r requirements-extras.txt
	touch $@

## figures: regenerate every paper figure (PNG and PDF) in paper_figures/output from the committed results
## (every script of paper_figures/, one after the other in one process: glamas.reproduce). It computes
## nothing: a missing or damaged committed result stops it with one line naming the script that recomputes it.
figures: $(READY)
	$(PY) -m glamas.reproduce --all

## test: every kernel compiled once into numba's cache (glamas.precompile, one process per core; the
## small run of every experiment it compiles with is checked against data/small_runs.json there, so the
## pytest session leaves out that test), then the unit tests and every notebook under nbval in one
## pytest session, on one worker per core (pytest-xdist; TEST_WORKERS=1 runs them one after the other;
## a notebook's cells run in order on one worker, in one kernel, and each worker keeps to a core: conftest.py)
TEST_WORKERS ?= auto
NBVAL := --nbval --nbval-current-env --nbval-sanitize-with notebooks/sanitize.cfg
CHECKED_BY_PRECOMPILE := --deselect tests/test_portable_results.py::test_a_small_run_gives_the_committed_bits

# The book's test builds the book in an environment of its own: `make book-check` runs it.
BOOK_TEST := --ignore=tests/test_book.py

test: $(READY) $(EXTRAS)
	$(PY) -m glamas.precompile --check
	$(PY) -m pytest -p no:cacheprovider -n $(TEST_WORKERS) $(NBVAL) $(CHECKED_BY_PRECOMPILE) $(BOOK_TEST) tests $(NOTEBOOKS)

unit: $(READY) $(EXTRAS)
	$(PY) -m pytest -p no:cacheprovider -n $(TEST_WORKERS) $(BOOK_TEST) tests

notebooks-check: $(READY)
	$(PY) -m pytest -p no:cacheprovider -n $(TEST_WORKERS) $(NBVAL) $(NOTEBOOKS)

## notebooks: re-execute every notebook in place at paper scale (commit the outputs)
notebooks: $(READY)
	@for nb in $(NOTEBOOKS); do echo "== $$nb"; $(PY) -m jupyter execute --inplace "$$nb" || exit 1; done

## lab: open the notebooks in JupyterLab (installs the optional extra "lab" first)
lab: $(READY)
	$(PY) -m pip install --quiet -e '.[lab]'
	$(PY) -m jupyter lab notebooks/

## book: the whole reproduction as one site in $(BOOK_OUT)/html (open $(BOOK_OUT)/html/index.html):
## the README as its front page, the notebooks in reading order with their committed outputs (nothing
## is executed), the ledger, the reproduction notes and docs/ (book/_toc.yml). Built by Sphinx in
## $(BOOK_VENV), made on first use from requirements-book.txt; any warning, a broken internal link
## included, fails it.
BOOK_VENV := .venv-book
BOOK_OUT ?= out/book
export BOOK_OUT

$(BOOK_VENV)/.installed: requirements-book.txt
	$(PYTHON) -m venv $(BOOK_VENV)
	$(BOOK_VENV)/bin/python -m pip install --quiet -r requirements-book.txt
	touch $@

book: $(BOOK_VENV)/.installed
	$(BOOK_VENV)/bin/python -m sphinx -W --keep-going -q -b html -c book -d "$$BOOK_OUT/doctrees" . "$$BOOK_OUT/html"

## book-check: tests/test_book.py: the book built, every page, image and internal link of its HTML
## checked, and (where chromium is installed) every image of its front page and of a notebook's page
## seen loaded in a headless browser
book-check: $(READY) $(BOOK_VENV)/.installed
	$(PY) -m pytest -p no:cacheprovider tests/test_book.py

## ledger: write docs/ledger.md, every claim's verdict, and README.md's count of verdicts from the committed results
ledger: $(READY)
	$(PY) -m glamas.ledger --write

## benchmark: compiled kernels against plain-Python references, and the time of `make figures`
## (each benchmark is a module of the package benchmarks: `python -m benchmarks.bench_gla --quick`)
BENCHMARKS := $(patsubst benchmarks/%.py,benchmarks.%,$(sort $(wildcard benchmarks/bench_*.py)))

benchmark: $(READY) $(EXTRAS)
	@for module in $(BENCHMARKS); do echo "== python -m $$module"; $(PY) -m $$module || exit 1; done

## reproduce: recompute every experiment of the chapter (Fig. 5-12) into $(OUT)/results and draw
## its figures into $(OUT)/figures, e.g. `make reproduce OUT=out/reproduce`. glamas.reproduce --fresh
## empties both first, after checking that $(OUT) holds only what glamas wrote and is not the
## repository's data/ or paper_figures/ (otherwise it refuses, deleting nothing), so the first
## script of each experiment recomputes it (as --rerun would) and the scripts drawing other figures
## of that experiment read what it just computed.
# OUT and VERIFY reach the commands through the environment ("$$OUT"): any path, spaces and
# quotes included, arrives as one argument.
OUT ?= out/reproduce
VERIFY ?= out/verify
export OUT VERIFY

reproduce: $(READY)
	$(PY) -m glamas.reproduce --fresh "$$OUT"

## verify: recompute every experiment (every script in paper_figures/) into $(VERIFY) as `make
## reproduce` does, and compare every result array and figure with the committed ones, both ways
## (a file on one side only is a difference), e.g. `make verify VERIFY=out/verify`.
## ADOPT=1: when nothing differs, the recomputed result files replace the committed ones (their records
## of the code that computed them are then the current code's: after a change of code that computes
## the same results)
ADOPT ?=
verify: $(READY)
	$(PY) -m glamas.reproduce --all --fresh "$$VERIFY"
	$(PY) -m glamas.verify "$$VERIFY" $(if $(ADOPT),--adopt)

## mutations: whether the small runs (data/small_runs.json) see a change of behaviour: each of a set of
## mutations of the kernels (a reward, a learning rate, a tie rule, a bounce, ...) made in a copy of the
## package, and the small runs of the experiments recording the mutated module computed there
## (benchmarks/small_run_mutations.py; about 18 minutes on 2 cores). Not run by make test.
mutations: $(READY)
	$(PY) -m benchmarks.small_run_mutations

## benchmark-maps: the sparse-interaction benchmark: every learner on the field's maps (TunnelToGoal
## with 2, 3 and 4 agents, ISR, CIT, CMU) against each map's exact optimum, under the chapter's rewards
## and under the field's, recomputed into $(MAPS_OUT)/results with its figures in $(MAPS_OUT)/figures
## (emptied first, as make reproduce does)
MAPS_OUT ?= out/benchmark-maps
export MAPS_OUT

benchmark-maps: $(READY)
	$(PY) -m glamas.reproduce --experiment benchmark_maps --fresh "$$MAPS_OUT"
	$(PY) -m glamas.reproduce --experiment benchmark_maps_field --out "$$MAPS_OUT/figures" --results "$$MAPS_OUT/results"

## benchmark-budgets: the same benchmark at 2,000, 20,000 and 200,000 training episodes per run under
## both formulations (the maps each learner's greedy policy solves after each budget), recomputed into
## $(BUDGETS_OUT)/results with its figure in $(BUDGETS_OUT)/figures (emptied first; about 22 minutes on 2 cores)
BUDGETS_OUT ?= out/benchmark-budgets
export BUDGETS_OUT

benchmark-budgets: $(READY)
	$(PY) -m glamas.reproduce --experiment benchmark_maps_budgets --fresh "$$BUDGETS_OUT"

## warehouses: many agents against a plan: every learner that fits on 16 generated warehouses of 8, 32
## and 128 agents, under both formulations, beside a prioritized plan of each instance, recomputed into
## $(WAREHOUSES_OUT)/results with its figure in $(WAREHOUSES_OUT)/figures (emptied first; about 25 minutes on 2 cores)
WAREHOUSES_OUT ?= out/warehouses
export WAREHOUSES_OUT

warehouses: $(READY)
	$(PY) -m glamas.reproduce --experiment warehouses --fresh "$$WAREHOUSES_OUT"

## pogema-crosscheck: the many-agent warehouses (N = 8, 32, 128, 1024) and their prioritized plans
## written as POGEMA tasks (benchmarks/pogema_tasks.py), then replayed and timed in POGEMA's own
## environment (benchmarks/pogema_replay.py, in $(POGEMA_VENV), made on first use from
## benchmarks/requirements-pogema.txt): CSR, ISR, sum of costs and makespan against the plan's, and
## POGEMA's ns per agent-step against glamas's (docs/speed.md; about 2 minutes). Not run by make test.
POGEMA_VENV := .venv-pogema
POGEMA_OUT ?= out/pogema

$(POGEMA_VENV)/.installed: benchmarks/requirements-pogema.txt
	$(PYTHON) -m venv $(POGEMA_VENV)
	$(POGEMA_VENV)/bin/python -m pip install --quiet -r benchmarks/requirements-pogema.txt
	touch $@

pogema-crosscheck: $(READY) $(POGEMA_VENV)/.installed
	mkdir -p "$(POGEMA_OUT)"
	$(PY) -m benchmarks.pogema_tasks "$(POGEMA_OUT)/tasks.json"
	$(POGEMA_VENV)/bin/python benchmarks/pogema_replay.py "$(POGEMA_OUT)/tasks.json"

clean-env:
	rm -rf "$(VENV)" "$(POGEMA_VENV)" "$(BOOK_VENV)"

## clean-cache: drop numba's compiled-kernel cache (glamas also drops it itself when its sources change)
clean-cache:
	find lib -name __pycache__ -type d -prune -exec rm -rf {} +
