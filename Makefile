# Two commands on a fresh machine: 'make demo' (set up + main job) and 'make test' (set up + tests).
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed
OUT ?= out

.PHONY: setup warm browser demo test test-slow bench bench-dist clean

$(STAMP): pyproject.toml constraints.txt
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -c constraints.txt -e '.[dev,mdf,dist]'
	touch $(STAMP)

setup: warm

demo: warm
	$(BIN)/vehicle-assist reproduce --out $(OUT)/reproduce

# compile the kernels of every shipped layout (and the batch path) into the cache once: a user's first run after
# 'make setup' loads compiled code instead of compiling it, and the two test workers do not both compile and
# write the same cache files at once (issue 13; vehicle_assist/_cache.py warm)
warm: $(STAMP)
	$(BIN)/python -c "from vehicle_assist._cache import warm; warm()"

# a real headless browser for the report test (tests/report/test_browser.py): Debian's chromium, installed only
# if missing and only when running as root (CI containers); otherwise that test skips and says why
browser:
	@command -v chromium >/dev/null 2>&1 || [ "$$(id -u)" != 0 ] || ! command -v apt-get >/dev/null 2>&1 || \
		(apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends chromium >/dev/null) || \
		echo "chromium not installed; the browser test will skip"

test: warm browser
	$(BIN)/python -m pytest -q -n 2

test-slow: warm
	$(BIN)/python -m pytest -q -n 2 -m slow

bench: $(STAMP)
	$(BIN)/python benchmarks/run.py

# the 100,000-variant sweep on a local dask cluster (issue #13): wall time, variants/s, client peak memory
bench-dist: $(STAMP)
	$(BIN)/python benchmarks/dist_sweep.py

clean:
	rm -rf $(VENV) $(OUT) .pytest_cache
