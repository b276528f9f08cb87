"""Fig. 5 tasks (validation/fig5_tasks.py, solvers/problems/gridshell_bh_weights.py): the arch crowns
that carry the pad, and the command line's one-line errors (InputError: exit 2 by the CLI)."""

import argparse

import numpy as np
import pytest

from lcefem.meshes.gridshell import build_gridshell_bar_hinge
from lcefem.models.errors import InputError
from lcefem.validation.commands import gridshell as gridshell_command
from lcefem.solvers.problems.gridshell_bh_weights import arch_crowns


def test_arch_crowns_are_the_highest_point_of_each_segment():
    s = build_gridshell_bar_hinge()
    x = s.nodes.copy()
    # a bump of 5 mm at the middle of every segment between two junctions (pitch 37 mm, at 52 and 89 mm)
    mids = np.array([52.0, 89.0])
    lines = np.array([33.5, 70.5, 107.5])
    along_x = np.min(np.abs(x[:, 0, None] - mids), axis=1) + np.min(np.abs(x[:, 1, None] - lines), axis=1)
    along_y = np.min(np.abs(x[:, 1, None] - mids), axis=1) + np.min(np.abs(x[:, 0, None] - lines), axis=1)
    x[:, 2] = 5.0 * np.exp(-np.minimum(along_x, along_y) ** 2 / 20.0)
    crowns = arch_crowns(s, x)
    assert crowns.size == 12
    p = s.nodes[crowns]
    # each crown sits at a segment's middle (within a panel) on a ribbon line
    mid = np.where(np.min(np.abs(p[:, 0, None] - lines), axis=1) < 1.0, p[:, 1], p[:, 0])
    assert np.all(np.min(np.abs(mid[:, None] - mids), axis=1) < 3.0)
    assert np.all(x[crowns, 2] > 4.0)


@pytest.mark.parametrize("args, message", [
    (["--scales"], "--scales: give --schedule FILE or --task"),
    (["--task", "ball", "--shape", "dome"], "--shape: not with --task"),
    (["--task", "weights", "--support", "rollers"], "--support/--thermal-model: not with --task weights"),
])
def test_task_option_errors(args, message):
    parser = argparse.ArgumentParser()
    gridshell_command.add_arguments(parser)
    with pytest.raises(InputError, match=message.replace("|", "\\|")):
        gridshell_command.prepare(parser.parse_args(args))
