# Two commands on a fresh machine (each creates .venv when missing):
#   make validate   - the main job: the validation report in results/validation
#   make test       - the test suite
.PHONY: env validate validate-quick test benchmark clean

env:
	@scripts/bootstrap.sh

validate: env
	.venv/bin/lcefem validate --overwrite --out results/validation

validate-quick: env
	.venv/bin/lcefem validate --quick --overwrite --out results/validation-quick

test: env
	.venv/bin/python -m pytest -n 2 --dist loadgroup -q

clean:
	rm -rf results .pytest_cache
