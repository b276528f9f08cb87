"""A block's heat exchange with the ribbon (Block.heat): the plate's law with the block's face in
place of the plate (solvers/der/heat.py SectionHeat.block_coefficients)."""

import math

import numpy as np
import pytest

from lcefem.models.contact import Block, ContactLaw
from lcefem.models.errors import InputError
from lcefem.models.heat import SurfaceExchange, ThermalProperties
from lcefem.models.ribbon import GroundHeatExchange, SectionGrid
from lcefem.solvers.der.heat import HeatGeometry, SectionHeat
from lcefem.solvers.der.model import Box


def test_box_normals_are_the_gradient_of_the_gaps():
    box = Box((-5.0, 0.0, -2.0), (5.0, 8.0, 6.0), 0.5)
    rng = np.random.default_rng(3)
    pts = rng.uniform([-8, -3, -4], [8, 11, 9], size=(200, 3))
    pts = pts[np.abs(box.gaps(pts)) > 0.05]  # away from the surface's kinks inside
    h = 1e-6
    grad = np.stack(
        [(box.gaps(pts + h * e) - box.gaps(pts - h * e)) / (2 * h) for e in np.eye(3)], axis=1
    )
    outside = box.gaps(pts) > 0
    np.testing.assert_allclose(box.normals(pts)[outside], grad[outside], atol=1e-6)
    np.testing.assert_allclose(np.linalg.norm(box.normals(pts), axis=1), 1.0, rtol=1e-12)


def test_block_temperature_choices():
    assert Block().block_temperature(100.0, 25.0) is None  # the default: no exchange (as before)
    assert Block(heat="plate").block_temperature(100.0, 25.0) == 100.0
    assert Block(heat="ambient").block_temperature(100.0, 25.0) == 25.0
    assert Block(heat="given", temperature=60.0).block_temperature(100.0, 25.0) == 60.0
    with pytest.raises(InputError, match="obstacle.heat"):
        Block(heat="warm").block_temperature(100.0, 25.0)


def test_still_section_against_a_hot_block_heats_at_the_contact_rate():
    """One lumped cell (1 x 1 grid), one 1 mm edge, far above the plate, with no air exchange and no
    radiation, its +m1 edge touching the near face of a block at 100 C: it exchanges only with the
    block, by contact conduction G_c l w(0) at each of its two touching corners (w(0) = 1/2) and the
    air film k_air/z0 over its t x l edge face, so T_b - T = (T_b - T_0) exp(-G t / C), G = l (G_c +
    k_air t/z0), C = rho c w t l (implicit Euler: (1 + dt/tau)^-n)."""
    w, t, l = 4.0, 0.8, 1.0
    grid = SectionGrid(w, t, 1, 1)
    thermal = ThermalProperties()
    ground = GroundHeatExchange(plate_emissivity=0.0)
    heat = SectionHeat(
        1,
        grid,
        np.array([l]),
        thermal,
        SurfaceExchange(film_coefficient=0.0, emissivity=0.0),
        ground,
        ContactLaw(),
    )
    geo = HeatGeometry(
        np.array([[0.5, 0.0, 1.0e6]]),
        np.array([[0.0, 1.0, 0.0]]),
        np.array([[0.0, 0.0, 1.0]]),
        np.array([l]),
        corner_gap=np.full((1, 4), 1.0e6),
    )
    box = Box((-10.0, 0.5 * w, 1.0e6 - 10.0), (10.0, 0.5 * w + 10.0, 1.0e6 + 10.0), 0.5)
    # corners (CORNER_SIGNS order) on the block's side are at gap 0, the others a width away
    from lcefem.models.rod import CORNER_SIGNS

    corner = np.where(CORNER_SIGNS[:, 0] > 0, 0.0, w)[None, :]
    T_b, T0, T_plate = 100.0, 25.0, 25.0
    G = l * (ground.contact_conductance + ground.air_conductivity * t / ground.gap_floor)
    C = thermal.volumetric_heat_capacity * w * t * l
    tau = C / G
    n = 200
    dt, T = tau / n, np.full((1, 1), T0)
    G_b, _, _, _ = heat.block_coefficients(T, geo, ((box, T_b, corner),))
    assert G_b[0, 0] == pytest.approx(G, rel=1e-6)
    for _ in range(n):
        T, _ = heat.step(T, dt, geo, T_plate, blocks=((box, T_b, corner),))
    # implicit Euler's own closed form (1 + dt/tau)^-n, within 0.1 K of the exact exp(-t/tau) at t =
    # tau (the plate, 1e6 mm below, still conducts ~1e-7 of G through the air: 2e-6 K here)
    assert T[0, 0] == pytest.approx(T_b - (T_b - T0) * (1.0 + dt / tau) ** -n, abs=1e-4)
    assert T[0, 0] == pytest.approx(T_b - (T_b - T0) * math.exp(-1.0), abs=0.1)
    # the same section without the block keeps its temperature (no other exchange)
    T_free, _ = heat.step(np.full((1, 1), T0), tau, geo, T_plate)
    assert T_free[0, 0] == pytest.approx(T0, abs=1e-3)


def test_ribbon_block_corner_gaps_and_heat_paths():
    """On a settled 11-node ribbon: a box whose top face is the plate gives the plate's corner gaps
    (RibbonSimulation.block_corner_gaps against corner_gaps); a block that exchanges no heat (the
    default) leaves the heat step's compiled path, and a block at a plate temperature of 100 C a
    millimetre from the ribbon's side warms the cells on that side more than a block at the
    air's."""
    from lcefem.solvers.der.ribbon import RibbonNumerics, RibbonSetup, RibbonSimulation

    num = RibbonNumerics(nodes=11, dt=0.02, settle_time=0.04)
    plain = RibbonSimulation(RibbonSetup(ground_temperature=100.0, numerics=num))
    plate_box = Box((-100.0, -100.0, -10.0), (200.0, 100.0, 0.0), 0.5)
    np.testing.assert_allclose(plain.block_corner_gaps(plate_box), plain.corner_gaps(), atol=1e-12)

    def block(heat):
        return Block(width=20.0, distance=2.0 + 1.0, direction=1.0, heat=heat)

    sims = {
        h: RibbonSimulation(RibbonSetup(ground_temperature=100.0, numerics=num, blocks=(block(h),)))
        for h in ("none", "ambient", "plate")
    }
    assert sims["none"].heated_blocks == () and len(sims["plate"].heated_blocks) == 1
    assert (
        sims["plate"].heated_blocks[0][1] == 100.0 and sims["ambient"].heated_blocks[0][1] == 25.0
    )
    for sim in (plain, *sims.values()):
        for _ in range(10):
            sim.step(0.02)
    np.testing.assert_array_equal(
        sims["none"].T, plain.T
    )  # no exchange: bit for bit the plate-only run
    rise = {h: sims[h].T - plain.T for h in ("ambient", "plate")}
    assert rise["plate"].max() > 0.0 > rise["ambient"].min()


def test_block_face_view_factor():
    """Facing a 20 x 10 mm face: ~1 at contact, the closed form of a centred square at a distance,
    and the plane's 1/2 at its edge line (a half-plane seen from its edge's foot)."""
    from lcefem.solvers.der.heat import block_face_view

    box = Box((-10.0, 5.0, -20.0), (10.0, 25.0, 20.0), 0.5)  # near face y = 5, 20 x 40 mm
    assert block_face_view(box, np.array([[0.0, 5.0 - 1e-6, 0.0]]), floor=-20.0)[
        0
    ] == pytest.approx(1.0, abs=1e-5)
    assert block_face_view(box, np.array([[0.0, 5.0 - 1e-6, 0.0]]))[0] == pytest.approx(
        0.5, abs=1e-5
    )  # on the floor
    # a centred 20 x 20 square (above the floor at 0 only half of it: 20 x 20 of the 20 x 40 face)
    d = 10.0
    a = 10.0 / d
    square = (
        4.0 * 2.0 * a / math.sqrt(1 + a * a) * math.atan(a / math.sqrt(1 + a * a)) / (2.0 * math.pi)
    )  # 0.554
    f = block_face_view(box, np.array([[0.0, 5.0 - d, 0.0]]), floor=-20.0)[0]
    g = block_face_view(box, np.array([[0.0, 5.0 - d, 10.0]]), floor=0.0)[
        0
    ]  # foot at the middle of 20 x 20
    assert g == pytest.approx(square, rel=1e-12)
    assert 0.0 < f < 1.0 and g < f


def test_case_file_rejects_an_unknown_block_heat():
    from lcefem.solvers.problems.twisted_ribbon_der import RibbonConfig

    with pytest.raises(
        InputError, match=r"obstacle.heat = 'hot': allowed none, plate, ambient, given"
    ):
        RibbonConfig(obstacle=Block(width=20.0, heat="hot")).validated()
