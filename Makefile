# Two commands on a fresh machine (each creates .venv when missing):
#   make validate   - the main job: the validation report in results/validation
#   make test       - the test suite
.PHONY: env validate validate-quick test benchmark clean

env:
	@scripts/bootstrap.sh

# Both farm the cases over one MPI rank per core (scripts/validate.sh; NPROC=1 for a serial run).
validate: env
	scripts/validate.sh --overwrite --out results/validation

validate-quick: env
	scripts/validate.sh --quick --overwrite --out results/validation-quick

test: env
	.venv/bin/python -m pytest -n 2 --dist loadgroup -q

clean:
	rm -rf results .pytest_cache
