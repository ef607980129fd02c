# The two set-up commands of the README: `make demo` and `make test`.
# Both create .venv with Python 3.11 and install the project into it first.
PYTHON ?= $(shell command -v python3.11 || command -v python3)
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed

.PHONY: demo test bench lint clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[test,cluster]'
	touch $(STAMP)

# The venv is not active in the shell that ran make: say how to type `lbw` (README "Set up").
demo: $(STAMP)
	@$(BIN)/lbw demo; status=$$?; \
	echo; echo "lbw is installed in $(VENV). To type 'lbw' in this shell: . $(VENV)/bin/activate"; \
	echo "(or call $(BIN)/lbw). Then: lbw --help, lbw run scenarios/build-table.yaml"; \
	exit $$status

test: $(STAMP)
	$(BIN)/python -m pytest -q -n 2

bench: $(STAMP)
	$(BIN)/python -m bench

lint: $(STAMP)
	$(BIN)/ruff check lbw_engine perception tests bench

clean:
	rm -rf $(VENV) build *.egg-info .pytest_cache
