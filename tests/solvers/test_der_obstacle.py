"""A rod thrown at a rigid wall (an obstacle plane with the ground's implicit contact law) does not
pass through it. Bound: with no load and implicit Euler (which never adds energy), the contact
energy k E(gap) at the deepest penetration p cannot exceed the initial kinetic energy, and
E >= p^2 for a point at depth p (the softplus is above its asymptote), so p <= sqrt(KE_0 / k)."""

import math

import numpy as np
import pytest

from lcefem.models.contact import ContactLaw, FrictionLaw
from lcefem.models.rod import rectangular_section
from lcefem.solvers.der.assembly import all_gaps
from lcefem.solvers.der.integrator import Integrator
from lcefem.solvers.der.model import DiscreteRod, Ground, RestShape, RodState, lumped_masses


@pytest.mark.parametrize("angle_deg", [0.0, 30.0])
def test_rod_thrown_at_a_wall_stays_out(angle_deg):
    n, speed, gap0 = 11, 100.0, 2.0  # nodes, approach speed [mm/s], start distance [mm]
    sec = rectangular_section(4.0, 0.8, 0.52, 0.175, 1.15e-9)
    rest = RestShape.straight(np.full(n - 1, 1.0))
    nm, ei = lumped_masses(sec, rest.edge_length)
    a = math.radians(angle_deg)
    normal = np.array([math.sin(a), math.cos(a), 0.0])  # wall turned by angle_deg about z
    x = np.zeros((n, 3))
    x[:, 0] = np.arange(n) - 0.5 * (n - 1)
    x[:, 2] = 50.0  # far above the ground: only the wall acts
    state = RodState.from_positions(x, first_director=np.array([0.0, 0.0, 1.0]))
    wall = Ground(
        tuple(normal), float(np.min(x @ normal)) - 2.0 - gap0
    )  # the nearest corner gap0 away
    law = ContactLaw()
    rod = DiscreteRod(
        sec, rest, nm, ei, ground=Ground(), contact=law, friction=FrictionLaw(), obstacles=(wall,)
    )
    state.v = np.tile(-speed * normal, (n, 1))
    kinetic = 0.5 * nm.sum() * speed**2  # [mJ]
    bound = math.sqrt(kinetic / law.stiffness)
    integ = Integrator(rod, state)
    deepest = np.inf
    for _ in range(200):  # 0.2 s: 20 mm of travel without the wall
        integ.step(1e-3)
        gs, ge = all_gaps(rod, integ.state, integ.sampling, wall)
        deepest = min(deepest, gs.min(), ge.min())
    assert -deepest <= bound
    assert bound < law.delta  # the check is sharper than "inside the smoothing band"
    assert np.mean(integ.state.v @ normal) > 0.0  # it bounced back
