"""benchmarks/gridshell_fe_recipes.py: a recipe the command refuses is reported as failed,
with the command's one-line reason and exit code, and no figures (the benchmark never reads a
summary the run did not write)."""

import gridshell_fe_recipes as bench


def test_a_refused_recipe_is_reported_with_its_reason(tmp_path):
    row = bench.run_recipe("no_such_recipe", 0, tmp_path, None)
    assert row["exit code"] == 2  # the house's exit code for bad input
    assert "--recipe" in row["error"] and "no_such_recipe" in row["error"]
    assert "dofs [-]" not in row and not (tmp_path / "no_such_recipe" / "summary.json").exists()
    assert row["cpu [s]"] > 0.0  # the child's CPU seconds are counted
