# Two commands on a fresh machine (each creates .venv when missing):
#   make validate   - the main job: the validation report in results/validation
#   make test       - the test suite
#   make docs       - the documentation site in docs/_build/html (warnings are errors)
.PHONY: env validate validate-quick test docs benchmark clean

env:
	@scripts/bootstrap.sh

# Both farm the cases over one MPI rank per core (scripts/validate.sh; NPROC=1 for a serial run).
validate: env
	scripts/validate.sh --overwrite --out results/validation

validate-quick: env
	scripts/validate.sh --quick --overwrite --out results/validation-quick

test: env
	.venv/bin/python -m pytest -n 2 --dist loadgroup -q

# -E: read every page again (autosummary regenerates the API pages), so a warning is never hidden
# by a cached page.
docs:
	@scripts/bootstrap.sh docs
	rm -rf docs/_autosummary docs/_generated
	.venv/bin/python -m sphinx -E -W --keep-going -q -b html docs docs/_build/html
	@echo "lcefem: documentation in docs/_build/html/index.html"

clean:
	rm -rf results .pytest_cache docs/_build docs/_autosummary docs/_generated
