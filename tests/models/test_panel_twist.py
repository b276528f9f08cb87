"""The Kapton panels' torsion (kapton.twist): the N5B8 ribbon's closed-form GJ, the plate's
G w t^3/3 with 'plate', bending and in-plane response unchanged, and the panel bending element's
derivatives."""

import dataclasses

import numpy as np
import pytest
import scipy.sparse.linalg as spla

from lcefem.meshes.bar_hinge_structure import n5b8_structure
from lcefem.models import bar_hinge as law
from lcefem.models import bar_hinge_materials as bhm
from lcefem.models.errors import InputError
from lcefem.solvers.bar_hinge import BarHingeModel

W_RIBBON, T_RIBBON = 7.0, 0.127  # the gridshell's ribbon [mm]


def ribbon(panel_length: float, panels: int):
    """A straight flat ribbon, one N5B8 panel across its 7 mm width."""
    x = np.linspace(0.0, panels * panel_length, panels + 1)
    coords = np.array([(xi, yi, 0.0) for xi in x for yi in (-0.5 * W_RIBBON, 0.5 * W_RIBBON)])
    quads = np.array([(2 * a, 2 * a + 2, 2 * a + 3, 2 * a + 1) for a in range(panels)])
    return n5b8_structure(coords, quads, T_RIBBON)


def end_energy(panel_length, panels, twist, mode, angle=1e-4):
    """Linear energy [mJ] of the ribbon whose last station is turned by ``angle`` about x (torsion),
    y (bending: the last two stations) or z (in plane), the first station(s) held."""
    s = ribbon(panel_length, panels)
    m = BarHingeModel(s, kapton=bhm.KaptonBarHinge(twist=twist))
    x0 = s.nodes
    n = x0.shape[0]
    u = np.zeros((n, 3))
    last = [2 * panels, 2 * panels + 1]
    if mode == "torsion":
        held = [0, 1] + last
        for i in last:
            u[i] = (0.0, x0[i, 1] * (np.cos(angle) - 1.0), x0[i, 1] * np.sin(angle))
    elif mode == "bending":
        held = [0, 1, 2, 3] + last + [2 * panels - 2, 2 * panels - 1]
        for i in last:
            u[i, 2] = angle * panel_length
    else:
        held = [0, 1] + last
        for i in last:
            u[i, 0] = -angle * x0[i, 1]
    k = m.hessian(x0.ravel()).tocsr()
    dofs = np.arange(3 * n).reshape(n, 3)
    pres = dofs[held].ravel()
    free = np.setdiff1d(dofs.ravel(), pres)
    uu = u.ravel()
    uu[free] = spla.spsolve(k[free][:, free].tocsc(), -k[free][:, pres] @ uu[pres])
    return 0.5 * uu @ (k @ uu)


def ribbon_gj(panel_length, twist, angle=1e-4):
    """GJ [N mm^2] from U = GJ angle^2/(2 L) + (end effects), two lengths."""
    (l1, u1), (l2, u2) = (
        (p * panel_length, end_energy(panel_length, p, twist, "torsion", angle)) for p in (14, 28)
    )
    return 2.0 * (u1 - u2) / (1.0 / l1 - 1.0 / l2) / angle**2


@pytest.mark.parametrize("panel_length", [2.3, 7.0])
def test_n5b8_ribbon_twists_as_its_closed_form_and_plate_as_the_plate_strip(panel_length):
    kap = bhm.KaptonBarHinge()
    k = kap.hinge_stiffness(T_RIBBON)
    # published: GJ = k D^3/(2 W): 60.7 N mm^2 (2.3 mm panels), 48.4 (7 mm), 10-14 x the plate's
    # (the two-length extrapolation leaves end effects of ~1e-6)
    gj = ribbon_gj(panel_length, "n5b8")
    assert gj == pytest.approx(law.n5b8_ribbon_twist_stiffness(k, panel_length, W_RIBBON), rel=1e-5)
    plate = kap.shear_modulus * W_RIBBON * T_RIBBON**3 / 3.0  # G w t^3/3 = 4.46 N mm^2
    assert plate == pytest.approx(4.4585, rel=1e-4)
    assert gj > 10.0 * plate
    assert ribbon_gj(panel_length, "plate") == pytest.approx(plate, rel=1e-5)


@pytest.mark.parametrize("mode", ["bending", "in plane"])
def test_plate_twist_leaves_bending_and_in_plane_response_unchanged(mode):
    a = end_energy(2.3, 12, "n5b8", mode)
    b = end_energy(2.3, 12, "plate", mode)
    assert a > 0 and b == pytest.approx(a, rel=1e-9)


def test_twist_fraction_is_symmetric_and_one_for_n5b8():
    kap = bhm.KaptonBarHinge(twist="plate")
    beta = law.panel_twist_fraction(kap, T_RIBBON, np.array([2.3, 7.0]), np.array([7.0, 2.3]))
    assert beta[0] == pytest.approx(beta[1], rel=1e-14)
    assert beta[0] == pytest.approx(4.4585 / 60.68, rel=1e-3)
    assert np.all(law.panel_twist_fraction(bhm.KaptonBarHinge(), T_RIBBON, 2.3, 7.0) == 1.0)
    with pytest.raises(InputError, match="kapton.twist"):
        bhm.KaptonBarHinge(twist="shell").checked()


def panel_state(rng, amplitude):
    """A 2.3 x 7 panel (centre, corners) perturbed by ``amplitude`` [mm]."""
    corners = np.array([(0.0, 0.0, 0.0), (2.3, 0.0, 0.0), (2.3, 7.0, 0.0), (0.0, 7.0, 0.0)])
    x = np.vstack([corners.mean(axis=0), corners])
    return x, x + amplitude * rng.standard_normal(x.shape)


def element(x, x_ref, k=0.7, derivatives=2):
    rest = np.array(
        [
            law.dihedral_angle(*(x_ref[None, s] for s in law.SPOKE_SLOTS[m]), derivatives=0)[0]
            for m in range(4)
        ]
    )[None, :]
    lengths = np.linalg.norm(x_ref[1:] - x_ref[0], axis=1)[None, :]
    return law.panel_bending_element(
        *(x[None, i] for i in range(5)), lengths, rest, np.array([k]), derivatives=derivatives
    )


def test_panel_element_stores_the_bending_mode_and_not_the_twist_or_rigid_motion():
    x_ref, _ = panel_state(np.random.default_rng(0), 0.0)
    c = 1e-3
    up = x_ref.copy()
    up[0, 2] += c  # the centre rises: the four spokes fold alike
    e_bend = element(up, x_ref, derivatives=0)[0]
    # four spokes of stiffness k fold by 2 c D/(W H) each: 4 k (D/2) (2 c D/(W H))^2/2
    d = np.hypot(2.3, 7.0)
    assert e_bend == pytest.approx(4 * 0.7 * (d / 2) * (2 * c * d / (2.3 * 7.0)) ** 2 / 2, rel=1e-5)
    tw = x_ref.copy()
    tw[1:, 2] += c * np.array([1.0, -1.0, 1.0, -1.0])  # corners up and down in turn
    assert element(tw, x_ref, derivatives=0)[0] < 1e-8 * e_bend
    rot = np.linalg.qr(np.random.default_rng(1).standard_normal((3, 3)))[0]
    rot *= np.sign(np.linalg.det(rot))
    assert element(x_ref @ rot.T + 3.0, x_ref, derivatives=0)[0] < 1e-20


def test_panel_element_derivatives_match_finite_differences():
    rng = np.random.default_rng(2)
    x_ref, x = panel_state(rng, 0.3)
    _, g, h = element(x, x_ref)
    v = rng.standard_normal(15)
    step = 1e-6
    xp, xm = x + step * v.reshape(5, 3), x - step * v.reshape(5, 3)
    fd = (element(xp, x_ref, derivatives=0)[0] - element(xm, x_ref, derivatives=0)[0]) / (2 * step)
    assert fd == pytest.approx(g[0] @ v, rel=1e-6)
    fd_h = (element(xp, x_ref, derivatives=1)[1][0] - element(xm, x_ref, derivatives=1)[1][0]) / (
        2 * step
    )
    assert np.allclose(fd_h, h[0] @ v, rtol=1e-5, atol=1e-8 * np.abs(h[0] @ v).max())
    assert np.allclose(h[0], h[0].T)


def test_assembled_plate_model_derivatives_match_finite_differences():
    s = ribbon(2.3, 4)
    m = BarHingeModel(s, kapton=bhm.KaptonBarHinge(twist="plate"))
    rng = np.random.default_rng(3)
    x = s.nodes.ravel() + 0.05 * rng.standard_normal(s.nodes.size)
    v = rng.standard_normal(x.size)
    step = 1e-6
    fd = (m.energy(x + step * v) - m.energy(x - step * v)) / (2 * step)
    assert fd == pytest.approx(m.gradient(x) @ v, rel=1e-6)
    fd_h = (m.gradient(x + step * v) - m.gradient(x - step * v)) / (2 * step)
    hv = m.hessian(x) @ v
    assert np.linalg.norm(fd_h - hv) < 1e-5 * np.linalg.norm(hv)
    # the panel elements are there, and the published model has none
    assert m.panel_set is not None and BarHingeModel(s).panel_set is None
    assert dataclasses.replace(bhm.KaptonBarHinge(), twist="plate").twist == "plate"
